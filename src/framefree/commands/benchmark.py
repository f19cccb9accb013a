"""``framefree benchmark``: the paper's protocol on a dataset folder, written out as Table I."""

from __future__ import annotations

import time
from pathlib import Path

import click

from .inputs import writable_file, writable_folder

__all__ = ["benchmark_command", "register"]


@click.command("benchmark")
@click.option(
    "--data",
    "data_dir",
    type=click.Path(file_okay=False, path_type=Path),
    default=None,
    help="Dataset folder <gesture>/<context>/<trial>.csv (default: the HPM replica).",
)
@click.option(
    "--model-context",
    default="original_1",
    show_default=True,
    help="Context whose trials are the 1-NN models.",
)
@click.option(
    "--methods",
    default="all",
    show_default=True,
    help="'all' (the 17 rows of Table I and the recommended row), 'paper' (the 17 rows), or "
    "e.g. 'bilts+:screw,dhb:arclength,rrv,recommended'.",
)
@click.option(
    "--contexts",
    default=None,
    help="Query contexts to use, comma-separated, or 'paper' (the paper's eleven query "
    "contexts); default: every context on disk. Training and test trials both come from them.",
)
@click.option(
    "--early",
    is_flag=True,
    help="Also measure early recognition (test trials cut to 25/50/75/100 %) for BILTS+ screw "
    "and the recommended row: early.json, early.md, early.png.",
)
@click.option(
    "--jobs",
    "-j",
    type=click.IntRange(min=1),
    default=None,
    help="Parallel workers, at least 1 (default: all cores; 1 runs in this process).",
)
@click.option(
    "--backend",
    type=click.Choice(["joblib", "dask", "ray"]),
    default="joblib",
    show_default=True,
    help="Where tasks run; dask and ray need the optional extras.",
)
@click.option(
    "--address",
    default=None,
    help="Scheduler address of an existing Dask or Ray cluster (the only way framefree reaches "
    "beyond 127.0.0.1; Ray needs one).",
)
@click.option(
    "--connect-timeout",
    type=click.FloatRange(min=0, min_open=True),
    default=10.0,
    show_default=True,
    help="Seconds to wait for the cluster at --address.",
)
@click.option(
    "--out",
    "out_dir",
    type=click.Path(file_okay=False, path_type=Path),
    default=Path("benchmark-results"),
    show_default=True,
    help="Folder for table1.md, table1.csv, results.json and the figures.",
)
@click.option(
    "--json",
    "json_file",
    type=click.Path(dir_okay=False, path_type=Path),
    default=None,
    help="Also write the JSON results here.",
)
@click.option(
    "--round-digits",
    type=int,
    default=None,
    help="Round descriptors to N significant digits, as the reference's CSV storage (5).",
)
@click.option(
    "--presmooth",
    type=int,
    default=None,
    metavar="W",
    help="framefree extension (not the paper's protocol): Gaussian-smooth the 50 Hz poses with "
    "a W-sample window before progress and descriptors.",
)
@click.option(
    "--figures/--no-figures",
    default=True,
    show_default=True,
    help="Write the heat map, confusion matrices and a DTW alignment figure.",
)
@click.option("--quiet", "-q", is_flag=True, help="No progress bar.")
def benchmark_command(
    data_dir: Path | None,
    model_context: str,
    methods: str,
    contexts: str | None,
    early: bool,
    jobs: int | None,
    backend: str,
    address: str | None,
    connect_timeout: float,
    out_dir: Path,
    json_file: Path | None,
    round_digits: int | None,
    presmooth: int | None,
    figures: bool,
    quiet: bool,
) -> None:
    """Train and test every method/progress row with the paper's protocol; write Table I.

    \b
    Models: all trials of the model context. Training: trials whose file name ends in 1 or 2 in
    every other context; each row's (x, L) grid is searched for the best pooled training
    recognition ratio (ties: smallest x, then smallest L). Test: the remaining trials.
    Outputs in --out: table1.md (ours beside the paper's numbers), table1.csv, results.json,
    heatmap.png, confusion/<row>.png, alignment.png.
    """
    from tqdm import tqdm

    from ..benchmark import load_benchmark_data, make_backend, run_benchmark

    specs = _method_specs(methods)
    if early:
        from ..benchmark import parse_methods

        specs += [s for s in parse_methods("bilts+:screw,recommended") if s not in specs]
    if json_file is not None:
        writable_file(json_file, "--json")
    writable_folder(out_dir)
    bk = make_backend(backend, jobs, address, connect_timeout)
    t0 = time.perf_counter()
    try:
        data = load_benchmark_data(data_dir, model_context, _parse_contexts(contexts))
    except BaseException:
        bk.close()
        raise
    load_s = time.perf_counter() - t0
    if not quiet:
        click.echo(f"{data.root}: {data.summary()}", err=True)
        click.echo(f"running {len(specs)} row(s) on {bk.describe()}", err=True)
    # created after the lines above, and shown once the first tasks are known: a bar printed
    # before them would share their line
    bar = tqdm(total=0, desc="benchmark", unit="task", disable=quiet, leave=False, delay=0.5)

    def grow(n: int) -> None:
        bar.total = (bar.total or 0) + n
        bar.refresh()

    with bk:
        result = run_benchmark(
            data,
            specs,
            bk,
            progress=bar.update,
            on_total=grow,
            round_digits=round_digits,
            presmooth=presmooth,
        )
    bar.close()
    result.timing["load"] = load_s
    result.timing["total"] += load_s

    _write_outputs(result, data, out_dir, json_file, figures, early, presmooth)


def _method_specs(methods: str) -> list:
    """The rows ``--methods`` names; says which Table I rows this installation lacks."""
    from ..benchmark import parse_methods
    from ..descriptors import available_descriptors

    try:
        specs = parse_methods(methods, available_descriptors())
    except ValueError as exc:
        raise click.BadParameter(str(exc), param_hint="--methods") from None
    if methods.strip().lower() == "all":
        from ..benchmark.grids import TABLE1_ROWS

        skipped = [r.key for r in TABLE1_ROWS if r not in specs]
        if skipped:
            msg = f"not registered in this installation, skipped: {', '.join(skipped)}"
            click.secho(msg, fg="yellow", err=True)
    return specs


def _write_outputs(result, data, out_dir: Path, json_file: Path | None, figures: bool,  # type: ignore[no-untyped-def]
                   early: bool = False, presmooth: int | None = None) -> None:
    """Table I (Markdown, CSV, JSON), the figures, and the table and timing on stdout."""
    from ..benchmark.results import markdown_table, write_csv, write_json, write_markdown

    written = [
        write_markdown(result, out_dir / "table1.md"),
        write_csv(result, out_dir / "table1.csv"),
        write_json(result, out_dir / "results.json"),
    ]
    if json_file is not None:
        written.append(write_json(result, json_file))
    if figures:
        written += _figures(result, data, out_dir)
    if early:
        written += _early(result, data, out_dir, presmooth)
    click.echo(markdown_table(result))
    t = result.timing
    click.echo(
        f"{len(result.rows)} row(s) in {t['total']:.1f} s wall-clock "
        f"(compute: descriptors {t['descriptors']:.1f} s, matching {t['matching']:.1f} s)"
    )
    for p in written:
        click.echo(f"wrote {p}", err=True)


def _parse_contexts(text: str | None) -> list[str] | None:
    """``--contexts``: None (all), ``paper`` (the paper's query contexts) or a comma list."""
    if text is None:
        return None
    if text.strip().lower() == "paper":
        from ..datasets.layout import CONTEXTS, MODEL_CONTEXT

        return [c for c in CONTEXTS if c != MODEL_CONTEXT]
    names = [c.strip() for c in text.split(",") if c.strip()]
    if not names:
        raise click.BadParameter("no context named", param_hint="--contexts")
    return names


def _early(result, data, out_dir: Path, presmooth: int | None) -> list[Path]:  # type: ignore[no-untyped-def]
    """Early recognition of BILTS+ screw and the recommended row."""
    from ..benchmark.early import early_markdown, early_recognition, plot_early, write_early_json

    rows = [r for r in result.rows if r.spec.key in ("bilts+:screw", "recommended")]
    res = early_recognition(data, rows, presmooth=presmooth)
    (out_dir / "early.md").write_text(early_markdown(res), encoding="utf-8")
    click.echo(early_markdown(res))
    return [
        write_early_json(res, out_dir / "early.json"),
        out_dir / "early.md",
        plot_early(res, out_dir / "early.png"),
    ]


def _figures(result, data, out_dir: Path) -> list[Path]:  # type: ignore[no-untyped-def]
    """Heat map, per-row confusion matrices and a DTW alignment of the first row."""
    from ..benchmark.figures import plot_aligned_signals, plot_confusion, plot_heatmap
    from ..core.trajectory import Trajectory
    from ..descriptors import get_descriptor
    from ..errors import FramefreeError

    out = [plot_heatmap(result, out_dir / "heatmap.png")]
    for row in result.rows:
        name = row.spec.key.replace(":", "_").replace("+", "plus")
        out.append(plot_confusion(row, result.gestures, out_dir / "confusion" / f"{name}.png"))
    if result.rows and data.models and data.test:
        # BILTS+ (else the best row) on a model and a test trial of the same gesture from a
        # body-frame context (else the last test trial)
        row = next((r for r in result.rows if r.spec.key == "bilts+:screw"), None)
        row = row or max(result.rows, key=lambda r: (r.mean, r.overall))
        q = next((r for r in data.test if r.context.startswith("body_frame")), data.test[-1])
        m = next((r for r in data.models if r.gesture == q.gesture), data.models[0])
        try:
            out.append(
                plot_aligned_signals(
                    get_descriptor(row.spec.method, **row.params),
                    Trajectory.from_array(m.data, m.source),
                    Trajectory.from_array(q.data, q.source),
                    out_dir / "alignment.png",
                    labels=(
                        f"{m.gesture}/{m.context}/{m.name}",
                        f"{q.gesture}/{q.context}/{q.name}",
                    ),
                )
            )
        except FramefreeError:
            pass
    return out


def register(group: click.Group) -> None:
    """Add ``benchmark`` to the ``framefree`` command group."""
    group.add_command(benchmark_command)
