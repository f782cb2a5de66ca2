"""The measure that follows the verdict: a design proven not to stand is shown at once, and its
measure (the tension QP: ``y / W^2``, the forces, the tension colours) is computed after.

A slider change on a design that needs tension is judged from the last design's multipliers
(:mod:`shapegen.statics.incremental`): the verdict is proven in a few hundredths of a second,
while the QP that gives the measure takes as long as a full solve. The session answers with
the verdict (``verdict.pending``: the measure is null) and hands the pending outcome to a
:class:`MeasureFollower`, whose thread completes the newest one (an older one, replaced by a
newer change meanwhile, is skipped) and gives it back to the session, which publishes it as a
new model version. Readouts that need the forces (the model, the scene, a block, the report)
wait for it.
"""

from __future__ import annotations

__all__ = ["MeasureFollower"]

import threading
from collections.abc import Callable

from shapegen import pipeline
from shapegen.errors import ShapegenError


class MeasureFollower:
    """Completes pending outcomes (:func:`shapegen.pipeline.completed`) in one thread.

    Parameters
    ----------
    publish
        Called from the thread with ``(pending, completed)`` for each outcome completed, or
        ``(pending, None)`` when its completion failed.
    """

    def __init__(self, publish: Callable[[object, object | None], None]):
        self._publish = publish
        self._condition = threading.Condition()
        self._wanted = None  # the newest pending outcome not yet started
        self._busy = None  # the one being completed
        self._stopped = False
        self._thread = threading.Thread(target=self._run, name="measure-follows", daemon=True)
        self._thread.start()

    def request(self, outcome) -> None:
        """Complete ``outcome`` (instead of any older one still waiting)."""
        with self._condition:
            self._wanted = outcome
            self._condition.notify_all()

    def wait(self, outcome) -> None:
        """Return once ``outcome`` is neither waiting nor being completed (it was published)."""
        with self._condition:
            self._condition.wait_for(
                lambda: self._stopped or (self._wanted is not outcome and self._busy is not outcome)
            )

    def stop(self) -> None:
        with self._condition:
            self._stopped = True
            self._wanted = None
            self._condition.notify_all()

    def _run(self) -> None:
        while True:
            with self._condition:
                self._condition.wait_for(lambda: self._stopped or self._wanted is not None)
                if self._stopped:
                    return
                outcome, self._wanted = self._wanted, None
                self._busy = outcome
            try:
                try:
                    done = pipeline.completed(outcome)
                except (ShapegenError, ArithmeticError, ValueError):
                    done = None  # the pending outcome stays: its verdict is proven
                self._publish(outcome, done)
            finally:
                with self._condition:
                    self._busy = None
                    self._condition.notify_all()
