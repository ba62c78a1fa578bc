"""Exceptions of viscoslide.

Bad input is a :class:`ValueError` naming the problem; file trouble an
:class:`OSError`; Ctrl-C during a solve a :class:`KeyboardInterrupt`; a
solve that did not converge a :class:`ConvergenceError`.
"""

from __future__ import annotations

from typing import List


class ConvergenceError(RuntimeError):
    """The contact iteration did not converge within its budget.

    Attributes
    ----------
    history : list of float
        Complementarity residual after each outer (active-set) iteration.
    iterations : int
        Outer iterations run.
    matvecs : int
        Applications of the influence operator.
    residual : float
        The last residual (the target is the ``tolerance`` of the solve).
    """

    def __init__(
        self,
        message: str,
        history: List[float],
        iterations: int,
        matvecs: int,
        residual: float,
    ) -> None:
        super().__init__(message)
        self.history = list(history)
        self.iterations = iterations
        self.matvecs = matvecs
        self.residual = residual
