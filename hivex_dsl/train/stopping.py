"""Stopping a training run cleanly: a signal or an event asks, the run finishes the update under way and writes its
checkpoint, curve and summary before it returns."""

from __future__ import annotations

import signal
import threading
from typing import Any


class StopRequests:
    """Within it, SIGINT (Ctrl-C) and SIGTERM set ``requested`` instead of killing the run, so training stops
    after the update under way and still writes its checkpoint, curve and summary. A second Ctrl-C kills.
    Only the main thread can take signals; elsewhere (a Ray task's thread) it requests nothing. ``also``, an
    event (``threading.Event`` or ``multiprocessing.Event``), requests a stop when set: a grid's parent process
    stops the points it runs in processes of their own through it."""

    SIGNALS = (signal.SIGINT, signal.SIGTERM)

    def __init__(self, also: Any = None) -> None:
        self._asked = False
        self._also = also
        self._previous: dict[int, Any] = {}

    @property
    def requested(self) -> bool:
        return self._asked or (self._also is not None and self._also.is_set())

    @requested.setter
    def requested(self, value: bool) -> None:
        self._asked = value

    def _request(self, signum: int, frame: Any) -> None:
        self.requested = True
        signal.signal(signal.SIGINT, self._previous.get(signal.SIGINT, signal.default_int_handler))

    def __enter__(self) -> "StopRequests":
        if threading.current_thread() is threading.main_thread():
            self._previous = {sig: signal.signal(sig, self._request) for sig in self.SIGNALS}
        return self

    def __exit__(self, *exc: Any) -> None:
        for sig, handler in self._previous.items():
            signal.signal(sig, handler)
