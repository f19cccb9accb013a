"""Options and checks shared by the commands: how pose files are read, where outputs may go.

Every command reads pose files with the same options (``--quat-order``, ``--units``,
``--skip-header``), takes models in either layout (:func:`framefree.datasets.resolve_models`) with
their own ``--model-quat-order``, and checks that its outputs can be written before it starts
computing: the one-line errors of a newcomer's first session, not a traceback at the end.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from ..core.posecsv import QUAT_ORDERS, UNITS
from ..errors import FramefreeError

if TYPE_CHECKING:
    from ..datasets.layout import ModelSet

__all__ = [
    "dataset_file_options",
    "model_options",
    "pose_file_options",
    "read_models",
    "writable_file",
    "writable_folder",
]


def _apply(func: Callable[..., Any], options: list[Callable[..., Any]]) -> Callable[..., Any]:
    for option in reversed(options):
        func = option(func)
    return func


_QUAT_ORDER = click.option(
    "--quat-order",
    default="wxyz",
    show_default=True,
    type=click.Choice(QUAT_ORDERS),
    help="Quaternion column order of the input pose files (not of the models).",
)
_UNITS = click.option(
    "--units",
    default="m",
    show_default=True,
    type=click.Choice(tuple(UNITS)),
    help="Unit of the positions in the pose files (models included).",
)
_SKIP_HEADER = click.option(
    "--skip-header", is_flag=True,
    help="The pose files (and --models files) start with a header row of other names than "
    "t,x,y,z,qw,qx,qy,qz (that one is always read as a header).")


def pose_file_options(func: Callable[..., Any]) -> Callable[..., Any]:
    """``--quat-order``, ``--units`` and ``--skip-header`` for the pose files a command reads."""
    return _apply(func, [_QUAT_ORDER, _UNITS, _SKIP_HEADER])


def dataset_file_options(func: Callable[..., Any]) -> Callable[..., Any]:
    """``--quat-order`` and ``--units`` for the files of a dataset folder."""
    return _apply(func, [_QUAT_ORDER, _UNITS])


def model_options(func: Callable[..., Any]) -> Callable[..., Any]:
    """``--model-context`` and ``--model-quat-order`` for a ``--models`` folder."""
    return _apply(
        func,
        [
            click.option(
                "--model-context",
                default="original_1",
                show_default=True,
                help="Context folder of the models when --models is a dataset root.",
            ),
            click.option(
                "--model-quat-order",
                default="wxyz",
                show_default=True,
                type=click.Choice(QUAT_ORDERS),
                help="Quaternion column order of the model files.",
            ),
        ],
    )


def read_models(folder: str | Path, model_context: str, quat_order: str, units: str,
                skip_header: bool = False) -> ModelSet:
    """Models from either layout (see :func:`~framefree.datasets.resolve_models`); says on stderr
    which layout it found. ``skip_header``: the model files start with a header row too."""
    from ..datasets.layout import resolve_models  # the dataset generators load on first use

    found = resolve_models(folder, model_context=model_context, quat_order=quat_order, units=units,
                           skip_header=skip_header)
    click.echo(found.description, err=True)
    return found


def writable_folder(path: str | Path, option: str = "--out") -> Path:
    """Create ``path`` (a folder) if needed; a one-line error if that is impossible."""
    path = Path(path)
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise FramefreeError(
            f"{path}: cannot create this output folder ({exc.strerror or exc}); choose another {option}"
        ) from None
    if not path.is_dir():
        raise FramefreeError(f"{path}: not a folder; choose another {option}")
    probe = path / ".framefree-write-test"
    try:
        probe.touch()
        probe.unlink()
    except OSError as exc:
        raise FramefreeError(
            f"{path}: cannot write here ({exc.strerror or exc}); choose another {option}"
        ) from None
    return path


def writable_file(path: str | Path, option: str = "--out") -> Path:
    """Check that the file ``path`` can be written (its folder is created if needed)."""
    path = Path(path)
    if path.is_dir():
        raise FramefreeError(f"{path}: is a folder; {option} needs a file name")
    writable_folder(path.parent if str(path.parent) else Path("."), option)
    return path
