"""framefree's main job, end to end: hand gestures → frame-free recognition → a robot stacks blocks.

1. the HPM replica (generated on first use and cached) supplies the gesture models (``original_1``);
2. a simulated person commands the robot through the paper's pick-and-place and stacking session
   (the paper's Table II; the scenario is described in ``docs/robot.md``): the same 18 commands in
   the same order and at the same times, walking between gestures (the tracker's world frame
   drifts) and re-gripping the tracker (its body frame changes), with distractor motions, tremor
   and tracker noise. The person watches the robot: when a command is not obeyed, they perform it again — as
   the paper's user did at 1:32, 2:06 and 2:31, which is how the paper's 18 commands became 21
   gestures. Who performs depends on the seed, and is always someone no parameter was tuned on
   (:func:`demo_person`);
3. the live recognizer (``method="segments"``, framefree's segment-spotting :class:`Recognizer`, or
   ``"paper"``, the paper's :class:`PaperRecognizer`, described in ``docs/online-paper.md``) turns
   the pose stream into events, sample by sample;
4. the planner, the Jacobian velocity controller and the joint impedance controller drive a
   simulated Franka Panda (MuJoCo) that should end with the green block stacked on the red one.

Each stage is a function of its own: :func:`build_recognizer`, :func:`build_loop` (the person and
the robot), :func:`~framefree.robot.closed_loop.run_commands` (the closed loop, module
:mod:`framefree.robot.closed_loop`), :func:`evaluate_loop` and :func:`write_outputs`; :func:`run_demo`
chains them. The robot side needs the ``robot`` extra (MuJoCo); ``make demo`` installs it.
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..labels import METHODS
from .closed_loop import ClosedLoop, PersonPolicy, _say, run_commands

if TYPE_CHECKING:
    from ..replica.people import Person

__all__ = [
    "DEMO_LEAD_IN",
    "DEMO_PEOPLE",
    "METHODS",
    "PAPER_RESULT",
    "ClosedLoop",
    "DemoResult",
    "PersonPolicy",
    "build_loop",
    "build_recognizer",
    "demo_commands",
    "demo_person",
    "evaluate_loop",
    "person_style",
    "run_commands",
    "run_demo",
    "write_outputs",
]

#: The paper's live result (the paper, Section V): 18 of 21 gestures detected, no false positive.
PAPER_RESULT = {"precision": 1.0, "recall": 18 / 21, "f1": 2 * (18 / 21) / (1 + 18 / 21)}
#: Seconds of stream before the first command (the paper's first gesture is at 0:31).
DEMO_LEAD_IN = 6.0
#: The people the demo draws its performer from: the held-out people, never used for tuning
#: (``framefree.replica.people.HELDOUT_PEOPLE``, written out so that the CLI starts without
#: loading the dataset generators; a test checks that they agree).
DEMO_PEOPLE = range(1000, 1020)
#: Recognition methods: framefree's segment-spotting recognizer (default) and the paper's.
#: Offset between the demo seed and the seed of the person's session (tremor, walks, grips).
_SESSION_SEED_OFFSET = 2026


@dataclass
class DemoResult:
    """Outcome of :func:`run_demo`.

    Attributes
    ----------
    recognition : dict
        Precision, recall, F1, false positives per minute and latencies over all performed gestures.
    obeyed : int
        Commands the robot received correctly (out of ``commands``).
    commands : int
        Commands the person meant to give.
    stacked : bool
        Whether the task succeeded (the green block rests on the red one).
    task : dict
        Final block offsets (see :class:`framefree.robot.scenario.StackResult`).
    events : list of dict
        Every recognition event with its verdict and the robot's reaction.
    files : dict of str to str
        Figures and data written.
    seconds : dict of str to float
        Wall time of each phase.
    method : str
        Recognition method (one of :data:`METHODS`).
    person_seed : int or None
        Seed of the performer (:func:`demo_person`).
    command_log : list of dict
        Per command: onset [s], gesture, attempts, whether the robot obeyed.
    missed : list of dict
        Performed gestures no event matched: label, start and end time [s], and what the
        recognizer saw of them (candidates classified, the smallest dissimilarity to the
        gesture's models among them, its threshold).
    """

    recognition: dict[str, Any]
    obeyed: int
    commands: int
    stacked: bool
    task: dict[str, Any]
    events: list[dict[str, Any]] = field(default_factory=list)
    files: dict[str, str] = field(default_factory=dict)
    seconds: dict[str, float] = field(default_factory=dict)
    method: str = "segments"
    person_seed: int | None = None
    command_log: list[dict[str, Any]] = field(default_factory=list)
    missed: list[dict[str, Any]] = field(default_factory=list)


def demo_commands(lead_in: float = DEMO_LEAD_IN) -> list[tuple[float, str]]:
    """The commands of the paper's session: (onset [s], gesture), 18 of them.

    The paper's 21 performed gestures, where a gesture that was not obeyed and then performed again
    counts once, at the time of its first attempt; shifted so that 0:31 becomes ``lead_in``.
    """
    from .scenario import PAPER_TIMELINE

    t0 = PAPER_TIMELINE[0][0]
    commands: list[tuple[float, str]] = []
    retry_of: str | None = None
    for t, performed, detected in PAPER_TIMELINE:
        if retry_of != performed:
            commands.append((t - t0 + lead_in, performed))
        retry_of = performed if detected != performed else None
    return commands


def demo_person(seed: int) -> Person:
    """The performer of demo session ``seed``: ``person(DEMO_PEOPLE[seed % len(DEMO_PEOPLE)])``.

    The demo draws only from the held-out people (seeds 1000-1019), never used to choose any
    parameter, so ``--seed 0`` (``make demo``) is person 1000 and seeds 20 apart share a person
    (with a different session: walks, grips, tremor and noise follow the seed itself).

    Parameters
    ----------
    seed : int
        Demo seed (non-negative).
    """
    from ..replica.people import person

    if int(seed) < 0:
        raise ValueError(f"demo seed must be non-negative, got {seed}")
    return person(DEMO_PEOPLE[int(seed) % len(DEMO_PEOPLE)])


def person_style(who: Person) -> dict[str, Any]:
    """The main style numbers of a person, JSON-friendly (times in s, lengths in m)."""
    return {
        "seed": who.seed,
        "tempo": who.tempo,
        "size": who.size,
        "skew": who.skew,
        "pause_s": list(who.pause),
        "rest_s": list(who.rest),
        "tremor": who.tremor,
        "variability": who.variability,
        "grip": who.grip,
        "stature_m": who.stature,
        "walk_speed_m_s": who.walk_speed,
    }


def build_recognizer(method: str = "segments", replica_seed: int = 0) -> Any:
    """Gesture models from the replica's ``original_1`` recordings, calibrated and warmed up.

    Parameters
    ----------
    method : {"segments", "paper", "window"}
        :class:`~framefree.online.Recognizer`, :class:`~framefree.online.paper.PaperRecognizer` or
        :class:`~framefree.online.window_baseline.WindowSpotter`.
    replica_seed : int
        Seed of the HPM replica (generated on first use, then cached).

    Returns
    -------
    Recognizer or PaperRecognizer
    """
    from ..online import Recognizer
    from ..online.paper import PaperRecognizer
    from ..online.window_baseline import WindowSpotter
    from ..replica import replica_path

    if method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}")
    cls = {"segments": Recognizer, "paper": PaperRecognizer, "window": WindowSpotter}[method]
    recognizer = cls.from_dataset(replica_path(replica_seed), model_context="original_1")
    recognizer.warmup()
    return recognizer


def build_loop(recognizer: Any, seed: int = 0, echo: Callable[[str], None] | None = None,
               robot: Any = None) -> ClosedLoop:
    """The person of demo session ``seed`` (:func:`demo_person`) and the robot, around a recognizer.

    Parameters
    ----------
    recognizer : Recognizer or PaperRecognizer
    seed : int
        Demo seed: picks the held-out person and seeds their session.
    echo : callable, optional
        Where the robot's reactions are reported.
    robot : RobotSim or RobotSession, optional
        Default: the MuJoCo stacking scene.
    """
    from ..replica import LivePerson

    who = demo_person(seed)
    return ClosedLoop(recognizer, LivePerson(seed + _SESSION_SEED_OFFSET, person=who), echo,
                      robot)


def evaluate_loop(loop: ClosedLoop, log: Any, method: str) -> DemoResult:
    """Score the session: events against the performed gestures, and the blocks at the end.

    Parameters
    ----------
    loop : ClosedLoop
        After :func:`run_commands`.
    log : SessionLog
        The robot's log.
    method : str
        Recorded in the result.

    Returns
    -------
    DemoResult
        Without ``files`` and ``seconds`` (filled by :func:`run_demo`).
    """
    from ..online.evaluation import match_events
    from .scenario import evaluate_stacking

    events = loop.tracer.events
    matched = match_events(events, loop.person.segments, loop.person.time)
    task = evaluate_stacking(log)
    rows = [
        {
            "time": ev.time,
            "label": ev.label,
            "dissimilarity": ev.dissimilarity,
            "model": ev.model,
            "verdict": detail["verdict"],
            "robot": loop.reactions.get(id(ev), "not reached"),
        }
        for ev, detail in zip(sorted(events, key=lambda e: e.time), matched.details, strict=True)
    ]
    who = loop.person.person
    return DemoResult(
        recognition=matched.summary(),
        obeyed=sum(c["obeyed"] for c in loop.command_log),
        commands=len(loop.command_log),
        stacked=bool(task.success),
        task={
            "horizontal_offset_m": task.horizontal_offset,
            "height_difference_m": task.height_difference,
            "tilt_rad": task.tilt,
            "moved_m": task.moved,
        },
        events=rows,
        method=method,
        person_seed=None if who is None else who.seed,
        command_log=list(loop.command_log),
        missed=_closest_approach(loop.tracer.trace(), matched.missed),
    )


def _closest_approach(trace: Any, missed: list[dict[str, Any]], slack: float = 1.0
                      ) -> list[dict[str, Any]]:
    """What the recognizer saw of each missed gesture: how many candidates it classified between
    the gesture's start and ``slack`` seconds after its end, the smallest dissimilarity to the
    gesture's own models among them (``closest``) and the gesture's threshold."""
    out = []
    for m in missed:
        row = {**m, "candidates": 0, "closest": None,
               "threshold": trace.thresholds.get(m["label"])}
        if m["label"] in trace.gestures and trace.times.size:
            during = (trace.times >= m["start_t"]) & (trace.times <= m["end_t"] + slack)
            own = trace.dissimilarity[during, trace.gestures.index(m["label"])]
            row["candidates"] = int(during.sum())
            if np.isfinite(own).any():
                row["closest"] = float(np.min(own))
        out.append(row)
    return out


def write_outputs(out: Path, loop: ClosedLoop, log: Any, render: bool,
                  echo: Callable[[str], None] | None = None) -> tuple[dict[str, str], float]:
    """The recognition timeline, the robot's paths and, when offscreen OpenGL works, images.

    Returns
    -------
    files : dict of str to str
        What was written.
    render_seconds : float
        Wall time spent rendering (0 when skipped).
    """
    from ..online.evaluation import plot_timeline
    from .render import plot_session, render_frames, rendering_available, save_gif, save_strip

    timeline = plot_timeline(out / "recognition_timeline.png", loop.person.segments,
                             loop.tracer.events, loop.tracer.trace(),
                             title="The paper's command session, recognized frame-free")
    files = {
        "recognition_timeline": str(timeline),
        "robot_session": str(plot_session(log, out / "robot_session.png", title="Stacking task")),
    }
    if not render:
        return files, 0.0
    ok, message = rendering_available()
    if not ok:
        _say(echo, f"3/3  no robot images: {message}")
        return files, 0.0
    tic = time.perf_counter()
    _say(echo, "3/3  rendering the robot ...")
    files["robot_strip"] = str(save_strip(render_frames(log, n_frames=8), out / "robot_strip.png"))
    frames = render_frames(log, n_frames=40, width=320, height=240)
    files["robot_gif"] = str(save_gif(frames, out / "robot_session.gif", fps=4))
    return files, time.perf_counter() - tic


def _summary(result: DemoResult, loop: ClosedLoop, recognizer: Any, seed: int, replica_seed: int,
             policy: PersonPolicy) -> dict[str, Any]:
    """The JSON summary of a session (see :func:`run_demo`)."""
    who = loop.person.person
    return {
        "seed": seed,
        "replica_seed": replica_seed,
        "method": result.method,
        "commands": result.commands,
        "gestures_performed": len(loop.person.segments),
        "obeyed": result.obeyed,
        "recognition": result.recognition,
        "paper": PAPER_RESULT,
        "missed": result.missed,
        "stacked": result.stacked,
        "task": result.task,
        "command_log": result.command_log,
        "events": result.events,
        "gesture_thresholds": recognizer.gesture_thresholds,
        "recognizer_stats": dict(getattr(recognizer, "stats", {})),
        "person": {
            "seed": result.person_seed,
            "session_seed": seed + _SESSION_SEED_OFFSET,
            "style": None if who is None else person_style(who),
            "watch_s": policy.watch,
            "max_repeats": policy.max_repeats,
        },
        "files": result.files,
        "seconds": result.seconds,
    }


def run_demo(
    out_dir: str | Path = "demo_output",
    seed: int = 0,
    render: bool = True,
    echo: Callable[[str], None] | None = print,
    progress: bool = True,
    commands: Sequence[tuple[float, str]] | None = None,
    policy: PersonPolicy | None = None,
    replica_seed: int = 0,
    method: str = "segments",
    recognizer: Any = None,
    models: str | Path | None = None,
) -> DemoResult:
    """Run the whole pipeline and write figures and a JSON summary into ``out_dir``.

    Parameters
    ----------
    out_dir : str or Path
        Folder for ``summary.json``, ``recognition_timeline.png``, ``robot_session.png`` and, when
        offscreen OpenGL works, ``robot_strip.png`` and ``robot_session.gif``.
    seed : int
        Demo seed: the performer is :func:`demo_person` ``(seed)``, a held-out person, and the seed
        also drives their session (walks, grips, tremor, noise). The gesture models always come
        from the replica of seed ``replica_seed``, as a real dataset is fixed.
    render : bool
        Try to render the robot (skipped with a message when no offscreen OpenGL is available).
    echo : callable, optional
        Where progress messages and events go (``None``: silent).
    progress : bool
        Show a progress bar.
    commands : sequence of (float, str), optional
        What the person wants the robot to do: (onset [s], gesture). Default:
        :func:`demo_commands`, the paper's session.
    policy : PersonPolicy, optional
        How the person reacts to the robot.
    replica_seed : int
        Seed of the HPM replica whose ``original_1`` trials are the gesture models.
    method : {"segments", "paper"}
        Recognizer (see :func:`build_recognizer`); ignored when ``recognizer`` or ``models`` is
        given.
    recognizer : Recognizer or PaperRecognizer, optional
        A ready recognizer (it is reset); saves building the models again across sessions.
    models : str or Path, optional
        A gesture library file (``framefree enroll``) to use instead of the replica's models; it
        must contain the seven HPM gestures.

    Returns
    -------
    DemoResult
        Also written, with the person's style, the per-command log and the thresholds, to
        ``summary.json``.
    """
    # robot.sim chooses MuJoCo's GL backend, which is fixed at mujoco's first import
    from . import sim as _sim  # noqa: F401  (import for its side effect)

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    policy = PersonPolicy() if policy is None else policy
    commands = demo_commands() if commands is None else list(commands)
    seconds: dict[str, float] = {}

    tic = time.perf_counter()
    recognizer = _demo_recognizer(recognizer, models, method, replica_seed, echo)
    method = getattr(recognizer, "method", "paper")
    seconds["models_and_calibration"] = time.perf_counter() - tic
    _say(echo, f"     {len(recognizer.labels)} models, {method} recognizer, thresholds calibrated")

    loop = build_loop(recognizer, seed, echo)
    style = person_style(loop.person.person)
    _say(echo, f"2/3  person {style['seed']} (tempo x{style['tempo']:.2f}, size x{style['size']:.2f}) "
               f"gives {len(commands)} commands by hand gestures (walking, re-gripping); the robot "
               "obeys through the recognizer, planner and controllers (MuJoCo) ...")
    tic = time.perf_counter()
    log = run_commands(loop, commands, policy, progress)
    seconds["session"] = time.perf_counter() - tic
    seconds["recognition_per_sample"] = loop.timing["recognition"] / max(loop.timing["samples"], 1)

    result = evaluate_loop(loop, log, method)
    result.files, render_seconds = write_outputs(out, loop, log, render, echo)
    if render_seconds:
        seconds["render"] = render_seconds
    result.seconds = seconds
    summary = _summary(result, loop, recognizer, seed, replica_seed, policy)
    (out / "summary.json").write_text(json.dumps(summary, indent=2, default=_jsonable))
    result.files["summary"] = str(out / "summary.json")
    return result


def _demo_recognizer(recognizer: Any, models: str | Path | None, method: str, replica_seed: int,
                     echo: Callable[[str], None] | None) -> Any:
    """The recognizer given, or one from a library file, or one built from the replica's models."""
    if recognizer is None and models is not None:
        from ..online import Recognizer

        _say(echo, f"1/3  gesture models: library {models} ...")
        recognizer = Recognizer.load(models)
        recognizer.warmup()
    if recognizer is None:
        _say(echo, f"1/3  gesture models ({method}): HPM replica (generated once, then cached) ...")
        recognizer = build_recognizer(method, replica_seed)
    return recognizer


def _jsonable(x: Any) -> Any:
    if isinstance(x, np.generic):
        return x.item()
    if isinstance(x, np.ndarray):
        return x.tolist()
    return str(x)
