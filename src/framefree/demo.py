"""framefree's main job, end to end: hand gestures → frame-free recognition → a robot stacks blocks.

1. the HPM replica (generated on first use and cached) supplies the gesture models (``original_1``);
2. a simulated person performs the paper's 21-gesture command session ([P2] Table II, ALGORITHMS
   §8.9) at its times, walking between gestures (the tracker's world frame drifts) and re-gripping
   the tracker (its body frame changes), with stops, distractor motions and tracker noise;
3. the live recognizer (streaming BILTS+, one incremental matcher per model, calibrated threshold,
   stop detector) turns the pose stream into events;
4. the planner, the Jacobian velocity controller and the joint impedance controller drive a
   simulated Franka Panda (MuJoCo) that should end with the green block stacked on the red one.

The robot side needs the ``robot`` extra (MuJoCo); ``make demo`` installs it.
"""

from __future__ import annotations

import json
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["DEMO_LEAD_IN", "PAPER_RESULT", "DemoResult", "demo_script", "run_demo"]

#: The paper's live result ([P2] §V): 18 of 21 gestures detected, no false positive.
PAPER_RESULT = {"precision": 1.0, "recall": 18 / 21, "f1": 2 * (18 / 21) / (1 + 18 / 21)}
#: Seconds of stream before the first gesture (the paper's first gesture is at 0:31).
DEMO_LEAD_IN = 6.0


@dataclass
class DemoResult:
    """Outcome of :func:`run_demo`.

    Attributes
    ----------
    recognition : dict
        Precision, recall, F1, false positives per minute and latencies against the script.
    stacked : bool
        Whether the task succeeded (the green block rests on the red one).
    task : dict
        Final block positions and offsets (see :class:`framefree.robot.scenario.StackResult`).
    events : list of dict
        Every recognition event with the robot's reaction.
    files : dict of str to str
        Figures and data written.
    seconds : dict of str to float
        Wall time of each phase.
    """

    recognition: dict[str, Any]
    stacked: bool
    task: dict[str, Any]
    events: list[dict[str, Any]] = field(default_factory=list)
    files: dict[str, str] = field(default_factory=dict)
    seconds: dict[str, float] = field(default_factory=dict)


def demo_script(lead_in: float = DEMO_LEAD_IN):
    """The person's script: the 21 performed gestures of the paper's timeline, shifted in time.

    Returns
    -------
    list of framefree.datasets.StreamItem
        One item per performed gesture, with the paper's onset minus 0:31 plus ``lead_in`` [s].
    """
    from .datasets import StreamItem
    from .robot.scenario import PAPER_TIMELINE

    t0 = PAPER_TIMELINE[0][0]
    return [StreamItem(performed, start_t=t - t0 + lead_in) for t, performed, _ in PAPER_TIMELINE]


def _say(echo: Callable[[str], None] | None, text: str) -> None:
    if echo is not None:
        echo(text)


def run_demo(
    out_dir: str | Path = "demo_output",
    seed: int = 0,
    render: bool = True,
    echo: Callable[[str], None] | None = print,
    progress: bool = True,
    script: list | None = None,
) -> DemoResult:
    """Run the whole pipeline and write figures and a JSON summary into ``out_dir``.

    Parameters
    ----------
    out_dir : str or Path
        Folder for ``summary.json``, ``recognition_timeline.png``, ``robot_session.png`` and, when
        offscreen OpenGL works, ``robot_strip.png`` and ``robot_session.gif``.
    seed : int
        Seed of the replica and of the simulated person.
    render : bool
        Try to render the robot (skipped with a message when no offscreen OpenGL is available).
    echo : callable, optional
        Where progress messages and events go (``None``: silent).
    progress : bool
        Show progress bars.
    script : list of framefree.datasets.StreamItem, optional
        What the person performs (default: :func:`demo_script`, the paper's 21 gestures).
    """
    # the robot module chooses MuJoCo's GL backend, which is fixed at mujoco's first import
    from tqdm import tqdm

    from .datasets import make_stream, replica_path
    from .online import Recognizer
    from .online.evaluation import match_events, plot_timeline, run_stream
    from .robot import sim as _sim  # noqa: F401  (import for its side effect)
    from .robot.render import plot_session, render_frames, rendering_available, save_gif, save_strip
    from .robot.scenario import (
        STACKING_PLANNER,
        STACKING_SCENE,
        STACKING_START,
        evaluate_stacking,
    )
    from .robot.session import RobotSim

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    seconds: dict[str, float] = {}

    tic = time.perf_counter()
    _say(echo, "1/4  gesture models: HPM replica (generated once, then cached) ...")
    root = replica_path(seed)
    recognizer = Recognizer.from_dataset(root, model_context="original_1")
    recognizer.warmup()
    seconds["models_and_calibration"] = time.perf_counter() - tic
    _say(echo, f"     {root}")
    _say(
        echo,
        f"     {len(recognizer.labels)} models, threshold {recognizer.threshold:.4g} (calibrated)",
    )

    tic = time.perf_counter()
    script = demo_script() if script is None else list(script)
    _say(echo, f"2/4  a person performs a {len(script)}-gesture session (walking, re-gripping) ...")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # onsets the person cannot meet are moved, as in reality
        traj, segments = make_stream(seed + 2026, sequence=script)
    seconds["person"] = time.perf_counter() - tic
    _say(
        echo, f"     {len(traj)} pose samples over {traj.duration:.0f} s, {len(segments)} gestures"
    )

    tic = time.perf_counter()
    _say(echo, "3/4  live recognition of the pose stream ...")
    events, trace = run_stream(recognizer, traj)
    seconds["recognition"] = time.perf_counter() - tic
    per_sample = seconds["recognition"] / len(traj)
    _say(echo, f"     {len(events)} events, {per_sample * 1e3:.2f} ms per pose sample")

    tic = time.perf_counter()
    _say(
        echo,
        "4/4  the robot executes the events (planner -> Jacobian velocity control -> "
        "joint impedance control, MuJoCo) ...",
    )
    reactions: dict[int, str] = {}

    def on_decision(decision) -> None:
        reactions[id(decision.event)] = decision.reason
        mark = "->" if decision.accepted else "--"
        _say(
            echo,
            f"     [{decision.event.time:6.1f} s] {decision.event.label:<14} "
            f"d={decision.event.dissimilarity:7.4f}  {mark} robot: {decision.reason}",
        )

    robot = RobotSim(
        planner=STACKING_PLANNER, scene=STACKING_SCENE, q0=STACKING_START, on_event=on_decision
    )
    for ev in events:
        robot.handle(ev)
    end = float(traj.t[-1]) + 4.0
    bar = tqdm(total=round(end), unit="sim s", disable=not progress, leave=False)
    robot.advance_to(end, progress=lambda t: bar.update(1))
    bar.close()
    log = robot.log()
    seconds["robot"] = time.perf_counter() - tic

    matched = match_events(events, segments, traj.duration)
    recognition = matched.summary()
    task = evaluate_stacking(log)
    files = {}
    files["recognition_timeline"] = str(
        plot_timeline(
            out / "recognition_timeline.png",
            segments,
            events,
            trace,
            recognizer.threshold,
            title="The paper's 21-gesture session, recognized frame-free",
        )
    )
    files["robot_session"] = str(
        plot_session(log, out / "robot_session.png", title="Stacking task")
    )
    if render:
        ok, message = rendering_available()
        if ok:
            tic = time.perf_counter()
            files["robot_strip"] = str(
                save_strip(render_frames(log, n_frames=8), out / "robot_strip.png")
            )
            files["robot_gif"] = str(
                save_gif(
                    render_frames(log, n_frames=40, width=320, height=240),
                    out / "robot_session.gif",
                    fps=4,
                )
            )
            seconds["render"] = time.perf_counter() - tic
        else:
            _say(echo, f"     (no robot images: {message})")

    event_rows = [
        {
            "time": ev.time,
            "label": ev.label,
            "dissimilarity": ev.dissimilarity,
            "model": ev.model,
            "verdict": detail["verdict"],
            "robot": reactions.get(id(ev), "not reached"),
        }
        for ev, detail in zip(sorted(events, key=lambda e: e.time), matched.details, strict=True)
    ]
    result = DemoResult(
        recognition=recognition,
        stacked=bool(task.success),
        task={
            "horizontal_offset_m": task.horizontal_offset,
            "height_difference_m": task.height_difference,
            "tilt_rad": task.tilt,
            "moved_m": task.moved,
        },
        events=event_rows,
        files=files,
        seconds=seconds,
    )
    summary = {
        "seed": seed,
        "recognition": recognition,
        "paper": PAPER_RESULT,
        "missed": matched.missed,
        "stacked": result.stacked,
        "task": result.task,
        "events": event_rows,
        "threshold": recognizer.threshold,
        "files": files,
        "seconds": seconds,
    }
    (out / "summary.json").write_text(json.dumps(summary, indent=2, default=_jsonable))
    files["summary"] = str(out / "summary.json")
    return result


def _jsonable(x: Any) -> Any:
    if isinstance(x, np.generic):
        return x.item()
    if isinstance(x, np.ndarray):
        return x.tolist()
    return str(x)
