"""framefree's main job, end to end: hand gestures → frame-free recognition → a robot stacks blocks.

1. the HPM replica (generated on first use and cached) supplies the gesture models (``original_1``);
2. a simulated person commands the robot through the paper's pick-and-place and stacking session
   ([P2] Table II, ALGORITHMS §8.9): the same 18 commands in the same order and at the same times,
   walking between gestures (the tracker's world frame drifts) and re-gripping the tracker (its body
   frame changes), with distractor motions, tremor and tracker noise. The person watches the robot:
   when a command is not obeyed, they perform it again — as the paper's user did at 1:32, 2:06 and
   2:31, which is how the paper's 18 commands became 21 gestures;
3. the live recognizer (streaming BILTS+, one incremental matcher per model, calibrated thresholds,
   stop detector) turns the pose stream into events, sample by sample;
4. the planner, the Jacobian velocity controller and the joint impedance controller drive a
   simulated Franka Panda (MuJoCo) that should end with the green block stacked on the red one.

The robot side needs the ``robot`` extra (MuJoCo); ``make demo`` installs it.
"""

from __future__ import annotations

import json
import time
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

__all__ = [
    "DEMO_LEAD_IN",
    "PAPER_RESULT",
    "DemoResult",
    "PersonPolicy",
    "demo_commands",
    "run_demo",
]

#: The paper's live result ([P2] §V): 18 of 21 gestures detected, no false positive.
PAPER_RESULT = {"precision": 1.0, "recall": 18 / 21, "f1": 2 * (18 / 21) / (1 + 18 / 21)}
#: Seconds of stream before the first command (the paper's first gesture is at 0:31).
DEMO_LEAD_IN = 6.0


@dataclass(frozen=True)
class PersonPolicy:
    """How the simulated person reacts to the robot.

    Attributes
    ----------
    watch : float
        After a gesture the person holds still this long [s] and watches whether the robot obeys
        (the recognizer decides within about 0.5 s of a gesture's end).
    max_repeats : int
        How often an ignored command is performed again (the paper's user repeated once).
    """

    watch: float = 1.5
    max_repeats: int = 2


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
    """

    recognition: dict[str, Any]
    obeyed: int
    commands: int
    stacked: bool
    task: dict[str, Any]
    events: list[dict[str, Any]] = field(default_factory=list)
    files: dict[str, str] = field(default_factory=dict)
    seconds: dict[str, float] = field(default_factory=dict)


def demo_commands(lead_in: float = DEMO_LEAD_IN) -> list[tuple[float, str]]:
    """The commands of the paper's session: (onset [s], gesture), 18 of them.

    The paper's 21 performed gestures, where a gesture that was not obeyed and then performed again
    counts once, at the time of its first attempt; shifted so that 0:31 becomes ``lead_in``.
    """
    from .robot.scenario import PAPER_TIMELINE

    t0 = PAPER_TIMELINE[0][0]
    commands: list[tuple[float, str]] = []
    retry_of: str | None = None
    for t, performed, detected in PAPER_TIMELINE:
        if retry_of != performed:
            commands.append((t - t0 + lead_in, performed))
        retry_of = performed if detected != performed else None
    return commands


def _say(echo: Callable[[str], None] | None, text: str) -> None:
    if echo is not None:
        echo(text)


def run_demo(
    out_dir: str | Path = "demo_output",
    seed: int = 0,
    render: bool = True,
    echo: Callable[[str], None] | None = print,
    progress: bool = True,
    commands: Sequence[tuple[float, str]] | None = None,
    policy: PersonPolicy | None = None,
    replica_seed: int = 0,
    models: str | Path | None = None,
) -> DemoResult:
    """Run the whole pipeline and write figures and a JSON summary into ``out_dir``.

    Parameters
    ----------
    out_dir : str or Path
        Folder for ``summary.json``, ``recognition_timeline.png``, ``robot_session.png`` and, when
        offscreen OpenGL works, ``robot_strip.png`` and ``robot_session.gif``.
    seed : int
        Seed of the simulated person's session (the gesture models always come from the replica
        of seed ``replica_seed``, as a real dataset is fixed).
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
    models : str or Path, optional
        A gesture library file (``framefree enroll``) to use instead of the replica's models; it
        must contain the seven HPM gestures.
    """
    from tqdm import tqdm

    from .datasets import LivePerson, replica_path
    from .online import Recognizer
    from .online.evaluation import TracingRecognizer, match_events, plot_timeline

    # robot.sim chooses MuJoCo's GL backend, which is fixed at mujoco's first import
    from .robot import sim as _sim  # noqa: F401  (import for its side effect)
    from .robot.render import plot_session, render_frames, rendering_available, save_gif, save_strip
    from .robot.scenario import STACKING_PLANNER, STACKING_SCENE, STACKING_START, evaluate_stacking
    from .robot.session import RobotSim

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    policy = PersonPolicy() if policy is None else policy
    commands = demo_commands() if commands is None else list(commands)
    seconds: dict[str, float] = {}

    tic = time.perf_counter()
    _say(echo, "1/3  gesture models: HPM replica (generated once, then cached) ...")
    root = replica_path(replica_seed) if models is None else Path(models)
    recognizer = (Recognizer.from_dataset(root, model_context="original_1") if models is None
                  else Recognizer.load(models))
    recognizer.warmup()
    seconds["models_and_calibration"] = time.perf_counter() - tic
    _say(echo, f"     {len(recognizer.labels)} models from {root}, thresholds calibrated")

    _say(
        echo,
        f"2/3  a person gives {len(commands)} commands by hand gestures (walking, re-gripping); "
        "the robot obeys through the recognizer, planner and controllers (MuJoCo) ...",
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

    person = LivePerson(seed + 2026)
    tracer = TracingRecognizer(recognizer)
    robot = RobotSim(
        planner=STACKING_PLANNER, scene=STACKING_SCENE, q0=STACKING_START, on_event=on_decision
    )
    tic = time.perf_counter()
    timing = {"recognition": 0.0, "robot": 0.0, "samples": 0}
    obeyed = 0

    def stream_to_robot() -> list:
        """Feed everything the person has done so far to the recognizer and the robot."""
        t0 = time.perf_counter()
        ts, ps, qs = person.samples_until()
        events = []
        for k in range(ts.shape[0]):
            for ev in tracer.push(ts[k], ps[k], qs[k]):
                robot.handle(ev)
                events.append(ev)
        t1 = time.perf_counter()
        if ts.size:
            robot.advance_to(float(ts[-1]))
        timing["recognition"] += t1 - t0
        timing["robot"] += time.perf_counter() - t1
        timing["samples"] += ts.shape[0]
        return events

    bar = tqdm(commands, unit="command", disable=not progress, leave=False)
    for onset, label in bar:
        for attempt in range(1 + policy.max_repeats):
            if attempt == 0:
                with warnings.catch_warnings():  # behind schedule after repeats: start late
                    warnings.simplefilter("ignore")
                    person.perform(label, start_t=max(onset, person.time))
            else:
                _say(echo, f"     [{person.time:6.1f} s] person: the robot ignored {label}; again")
                person.perform(label, gap=0.0)
            person.hold(policy.watch)
            if any(ev.label == label for ev in stream_to_robot()):
                obeyed += 1
                break
    bar.close()
    person.hold(3.0)
    stream_to_robot()
    robot.advance_to(person.time + 2.0)
    log = robot.log()
    seconds["session"] = time.perf_counter() - tic
    seconds["recognition_per_sample"] = timing["recognition"] / max(timing["samples"], 1)

    events = tracer.events
    matched = match_events(events, person.segments, person.time)
    recognition = matched.summary()
    task = evaluate_stacking(log)
    files = {
        "recognition_timeline": str(
            plot_timeline(
                out / "recognition_timeline.png",
                person.segments,
                events,
                tracer.trace(),
                title="The paper's command session, recognized frame-free",
            )
        ),
        "robot_session": str(plot_session(log, out / "robot_session.png", title="Stacking task")),
    }
    if render:
        ok, message = rendering_available()
        if ok:
            tic = time.perf_counter()
            _say(echo, "3/3  rendering the robot ...")
            strip = render_frames(log, n_frames=8)
            files["robot_strip"] = str(save_strip(strip, out / "robot_strip.png"))
            frames = render_frames(log, n_frames=40, width=320, height=240)
            files["robot_gif"] = str(save_gif(frames, out / "robot_session.gif", fps=4))
            seconds["render"] = time.perf_counter() - tic
        else:
            _say(echo, f"3/3  no robot images: {message}")

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
        obeyed=obeyed,
        commands=len(commands),
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
        "replica_seed": replica_seed,
        "commands": len(commands),
        "gestures_performed": len(person.segments),
        "obeyed": obeyed,
        "recognition": recognition,
        "paper": PAPER_RESULT,
        "missed": matched.missed,
        "stacked": result.stacked,
        "task": result.task,
        "events": event_rows,
        "gesture_thresholds": recognizer.gesture_thresholds,
        "person": {"watch_s": policy.watch, "max_repeats": policy.max_repeats},
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
