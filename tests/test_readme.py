"""Every Python block and command of README.md runs as written, on the replica.

The fenced ``python`` and ``bash`` blocks are extracted and run in order in one fresh working folder
(``framefree`` is this checkout's CLI). Whatever blocks the README has are run; the few that need a
live publisher, a person's own file or a long run are listed in :data:`SHORTENED` with the explicit,
shortened way they are run instead — none is skipped. A README example that fails fails this test.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import socket
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
README = REPO / "README.md"
FENCE = re.compile(r"^```(\w*)[^\n]*\n(.*?)^```", re.MULTILINE | re.DOTALL)

#: files the README names as the reader's own, and the replica files that stand in for them
PLACEHOLDER_FILES = {
    "recording.csv": "hpm_replica/go_up/original_1/trial_1.csv",
    "s1.csv": "hpm_replica/streams/stream_1.csv",
    "s2.csv": "hpm_replica/streams/stream_2.csv",
    "/path/to/HPM": "hpm_replica",
}

#: commands run in a shortened form: (pattern the README line starts with, what is run instead,
#: why). ``{}`` stands for the README line.
SHORTENED = [
    ("make demo", "make -n demo", "the whole demo: its make target is checked (dry run)"),
    ("make test", "make -n test", "would run this test suite again: dry run"),
    ("source .venv/bin/activate", f"test -e {Path(sys.prefix) / 'bin' / 'activate'}",
     "a shell builtin: the environment running these tests has the activate script"),
    ("framefree benchmark --out", "{} --methods bilts+:screw --no-figures",
     "all 17 rows take minutes on a shared machine: one row"),
    ("framefree benchmark --methods", "{} --no-figures", "no figures (the first run drew them)"),
    ("framefree benchmark --contexts", "{} --methods bilts+:screw --no-figures",
     "all 18 rows over the paper's contexts take two minutes: one row"),
    ("framefree evaluate-stream --models ../shared/data/sfinge_dev/templates",
     "framefree evaluate-stream --models hpm_replica --gestures go_left,go_right "
     "hpm_replica/streams/stream_1.csv",
     "SFINGE3D is not shipped (no licence): the same options on the replica's first stream"),
    ("framefree stream hpm_replica/streams/stream_1.csv", "{} --rate 500",
     "at the README's 50 poses a second the stream takes its three minutes: ten times faster "
     "(the last --rate given counts; live takes the poses several times faster than that)"),
]

#: a Python block that iterates over a live ``source`` gets one: the replica trial replayed
LIVE_SOURCE_PRELUDE = (
    "from framefree.online import CsvReplay\n"
    "source = CsvReplay('recording.csv', speed=0)   # README: a live pose source\n"
)


@dataclass
class Block:
    lang: str
    text: str
    line: int


def readme_blocks() -> list[Block]:
    text = README.read_text()
    return [
        Block(m.group(1), m.group(2), text.count("\n", 0, m.start()) + 1)
        for m in FENCE.finditer(text)
        if m.group(1) in ("python", "bash")
    ]


def commands(block: Block) -> list[str]:
    """The command lines of a bash block, comments removed."""
    out = []
    for line in block.text.splitlines():
        line = re.sub(r"\s+#.*$", "", line).strip()
        if line and not line.startswith("#"):
            out.append(line)
    return out


def _env() -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(REPO / "src"), env.get("PYTHONPATH", "")])
    env["MPLBACKEND"] = "Agg"
    return env


#: the README's example port, replaced by a free one (other programs may hold it)
README_PORT = "5555"


def _free_port() -> str:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return str(s.getsockname()[1])


PORT = _free_port()


def _argv(line: str) -> list[str]:
    argv = shlex.split(line.replace(f":{README_PORT}", f":{PORT}").replace(
        f"--port {README_PORT}", f"--port {PORT}"))
    for k, arg in enumerate(argv):
        argv[k] = PLACEHOLDER_FILES.get(arg, arg)
    if argv[0] == "framefree":
        argv = [sys.executable, "-m", "framefree.cli", *argv[1:]]
    elif argv[0] == "make":
        argv = [*argv, "-C", str(REPO)]
    return argv


def _shortened(line: str) -> str:
    for start, instead, _why in SHORTENED:
        if line.startswith(start):
            return instead.format(line)
    return line


def _check(proc: subprocess.CompletedProcess, what: str) -> None:
    assert proc.returncode == 0, f"{what} failed ({proc.returncode}):\n{proc.stdout}\n{proc.stderr}"
    assert "Traceback" not in proc.stderr, f"{what}:\n{proc.stderr}"


def _run(line: str, cwd: Path, timeout: float = 600) -> subprocess.CompletedProcess:
    proc = subprocess.run(_argv(_shortened(line)), cwd=cwd, env=_env(), capture_output=True,
                          text=True, timeout=timeout)
    _check(proc, f"README command {line!r}")
    return proc


def _stream_and_live(publish: str, subscribe: str, cwd: Path) -> None:
    """The two-terminal example: ``live`` subscribes first, ``stream`` publishes; both must end by
    themselves (the end-of-stream message) and ``live`` must have received every pose."""
    live = subprocess.Popen(_argv(subscribe + " --timeout 120 --no-view"), cwd=cwd, env=_env(),
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        time.sleep(2.0)  # live connects before it builds its models; messages then queue
        pub = subprocess.run(_argv(_shortened(publish)), cwd=cwd, env=_env(),
                             capture_output=True, text=True, timeout=300)
        _check(pub, f"README command {publish!r}")
        out, err = live.communicate(timeout=300)
    finally:
        if live.poll() is None:
            live.kill()
    assert live.returncode == 0, f"{subscribe!r} failed:\n{out}\n{err}"
    sent = int(re.search(r"sent (\d+) poses", pub.stderr).group(1))
    got = int(re.search(r"^(\d+) poses;", err, re.MULTILINE).group(1))
    assert got == sent > 0, (sent, got, err)


def _python(block: Block, cwd: Path) -> None:
    code = block.text
    if re.search(r"\bin source\b", code) and "source =" not in code:
        code = LIVE_SOURCE_PRELUDE + code
    script = cwd / f"readme_block_line{block.line}.py"
    script.write_text(code)
    proc = subprocess.run([sys.executable, str(script)], cwd=cwd, env=_env(), capture_output=True,
                          text=True, timeout=600)
    _check(proc, f"README Python block at line {block.line}")


def _placeholders(cwd: Path) -> None:
    for name, replica_file in PLACEHOLDER_FILES.items():
        if not name.startswith("/") and (cwd / replica_file).is_file():
            shutil.copy(cwd / replica_file, cwd / name)
            labels = (cwd / replica_file).with_name(Path(replica_file).stem + "_labels.csv")
            if labels.is_file():
                shutil.copy(labels, cwd / f"{Path(name).stem}_labels.csv")


def test_readme_has_the_examples_it_promises():
    blocks = readme_blocks()
    assert any(b.lang == "python" for b in blocks) and any(b.lang == "bash" for b in blocks)
    lines = [c for b in blocks if b.lang == "bash" for c in commands(b)]
    assert "framefree dataset make --out hpm_replica" in lines[:4] + lines


@pytest.mark.slow
def test_every_readme_block_runs(tmp_path):
    blocks = readme_blocks()
    # the replica first: the README's own command makes it, and the stand-in files come from it
    made = False
    for block in blocks:
        if block.lang == "bash":
            for line in commands(block):
                if line.startswith("framefree dataset make"):
                    _run(line, tmp_path)
                    made = True
    assert made, "README.md no longer makes the replica"
    _placeholders(tmp_path)
    # the README's real-data examples name tests/data/... as seen from the repository root
    (tmp_path / "tests").mkdir()
    (tmp_path / "tests" / "data").symlink_to(REPO / "tests" / "data")
    for block in blocks:
        if block.lang == "python":
            _python(block, tmp_path)
            continue
        lines = [c for c in commands(block) if not c.startswith("framefree dataset make")]
        publish = next((c for c in lines if c.startswith("framefree stream")), None)
        subscribe = next((c for c in lines if c.startswith("framefree live")), None)
        if publish and subscribe:
            _stream_and_live(publish, subscribe, tmp_path)
        for line in lines:
            if line not in (publish, subscribe):
                _run(line, tmp_path)
    # what the README says the commands write, they wrote — and the replica is untouched
    assert (tmp_path / "hpm_replica_gallery.png").is_file()
    assert not list((tmp_path / "hpm_replica").glob("*.png"))
    # run from the repository root, nothing the examples wrote would be an untracked file
    written = {p.name for p in tmp_path.iterdir()} - _TEST_ARTIFACTS - set(PLACEHOLDER_FILES)
    written = {n for n in written if not n.startswith("readme_block_line")
               and not n.endswith("_labels.csv")}
    as_paths = [f"{n}/" if (tmp_path / n).is_dir() else n for n in written]
    assert as_paths and not [n for n in as_paths if not _ignored(n)], as_paths


#: what this test itself puts in the working folder (the stand-in files, the tests/data link)
_TEST_ARTIFACTS = {"tests"}

#: options whose value is a file or folder a README command writes
_OUTPUT_OPTIONS = ("--out", "-o", "--json", "--save", "--library", "--figures")


def _ignored(path: str) -> bool:
    """Whether the repository's .gitignore ignores ``path`` (relative to the repository root)."""
    git = shutil.which("git")
    if git is None:
        pytest.skip("git is not installed")
    proc = subprocess.run([git, "check-ignore", "--no-index", "-q", path], cwd=REPO)
    if proc.returncode == 128:
        pytest.skip("not a git checkout")
    return proc.returncode == 0


def readme_outputs() -> list[str]:
    """Every file or folder the README's commands and Python blocks name as an output."""
    out = []
    for block in readme_blocks():
        if block.lang == "python":
            out += re.findall(r"(?:to_csv|save_stream)\(\"([^\"]+)\"", block.text)
            continue
        for line in commands(block):
            argv = shlex.split(line)
            out += [argv[k + 1] for k, a in enumerate(argv[:-1]) if a in _OUTPUT_OPTIONS]
            out += [a[len("jsonl:"):] for a in argv if a.startswith("jsonl:") and a != "jsonl:-"]
    return out


def test_readme_outputs_are_distinct_and_ignored_by_git():
    """No two examples write the same file, and everything they write is ignored by git when they
    are run from the repository root (under out/, or the replica they make)."""
    outputs = [o.rstrip("/") for o in readme_outputs()]
    assert len(outputs) >= 10, outputs
    assert len(set(outputs)) == len(outputs), sorted(o for o in outputs if outputs.count(o) > 1)
    assert not [o for o in outputs if not _ignored(o)]
