"""Progress reporting: ``progress=None`` reports nothing, ``True`` shows a
tqdm bar (when tqdm is installed), a callable receives a dict per event;
anything else (``progress=1``) is a TypeError."""

from __future__ import annotations

import contextlib
import warnings
from typing import Any, Callable, Dict, Iterator, Optional

Callback = Callable[[Dict[str, Any]], None]


def _tqdm(**kwargs: Any) -> Any:
    try:
        from tqdm.auto import tqdm
    except ImportError:
        warnings.warn("progress=True needs tqdm (pip install tqdm); no progress is shown", stacklevel=4)
        return None
    return tqdm(**kwargs)


@contextlib.contextmanager
def iterations(progress: Any) -> Iterator[Optional[Callback]]:
    """The callback of one solve: called after every outer iteration with
    ``{"iteration", "matvecs", "residual", "contact_cells"}``, and in a
    heated solve ``"stage"`` too (the evaluation the iteration belongs to)."""
    if progress is None or progress is False:
        yield None
        return
    if callable(progress):
        yield progress
        return
    if progress is not True:
        raise TypeError(f"progress must be None, True or a callable, got {progress!r}")
    bar = _tqdm(desc="active-set iterations", unit="it", leave=False)
    if bar is None:
        yield None
        return

    def update(info: Dict[str, Any]) -> None:
        bar.update(1)
        if "stage" in info:
            bar.set_description(info["stage"], refresh=False)
        bar.set_postfix(residual=f"{info['residual']:.2e}", contact=info["contact_cells"], refresh=False)

    try:
        yield update
    finally:
        bar.close()


@contextlib.contextmanager
def points(progress: Any, total: int) -> Iterator[Optional[Callback]]:
    """The callback of a sweep: called after every point with ``{"point",
    "points", "speed", "friction_coefficient", ...}``."""
    if progress is None or progress is False:
        yield None
        return
    if callable(progress):
        yield progress
        return
    if progress is not True:
        raise TypeError(f"progress must be None, True or a callable, got {progress!r}")
    bar = _tqdm(total=total, desc="sweep", unit="point")
    if bar is None:
        yield None
        return

    def update(info: Dict[str, Any]) -> None:
        bar.update(1)
        bar.set_postfix(mu=f"{info['friction_coefficient']:.3e}", refresh=False)

    try:
        yield update
    finally:
        bar.close()
