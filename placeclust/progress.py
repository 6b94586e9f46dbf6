"""Progress that reads well both on a terminal and in a log.

On a terminal :func:`progress` is a tqdm bar. Anywhere else (CI, a pipe, ``make demo > log``) a
bar would write a line per update and bury the report, so it prints a few summary lines
instead: one at each quarter of the work and one when it ends.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Iterable, Iterator, Sized
from typing import Any, TextIO


def progress(iterable: Iterable | None = None, *, total: int | None = None, desc: str = "",
             unit: str = "it", enabled: bool = True, file: TextIO | None = None) -> Any:
    """A progress bar over ``iterable`` (or ``total`` steps of ``update()``).

    Args:
        iterable: what to iterate over, or ``None`` for a bar advanced by ``update(n)``.
        total: number of steps; defaults to ``len(iterable)`` where it has one.
        desc: label of each line.
        unit: what one step is called (``frame``, ``job``).
        enabled: ``False`` shows nothing at all.
        file: where lines go (default ``sys.stderr``).

    Returns:
        An object with tqdm's ``update``, ``close`` and iteration, usable as a context manager.

    Examples:
        >>> import io
        >>> log = io.StringIO()
        >>> sum(progress(range(8), desc="demo", unit="frame", file=log))
        28
        >>> lines = log.getvalue().splitlines()
        >>> len(lines), lines[1].split(",")[0], lines[-1].split(" in ")[0]
        (4, 'demo: 4/8 frames (50%)', 'demo: 8 frames')
        >>> log = io.StringIO()
        >>> _ = list(progress(range(7), desc="jobs", unit="job", file=log))
        >>> [line.split(",")[0] for line in log.getvalue().splitlines()][:2]
        ['jobs: 2/7 jobs (28%)', 'jobs: 4/7 jobs (57%)']
    """
    file = sys.stderr if file is None else file
    if total is None and isinstance(iterable, Sized):
        total = len(iterable)
    if enabled and file.isatty():
        from tqdm import tqdm

        return tqdm(iterable, total=total, desc=desc, unit=unit, file=file)
    return LogProgress(iterable, total, desc, unit, file, quiet=not enabled)


class LogProgress:
    """tqdm's interface as a few lines of text: each quarter of ``total``, then the end."""

    def __init__(self, iterable: Iterable | None, total: int | None, desc: str, unit: str,
                 file: TextIO, quiet: bool = False) -> None:
        self.iterable, self.total, self.desc, self.unit = iterable, total, desc, unit
        self.file, self.quiet = file, quiet
        self.n = 0
        self._start = time.perf_counter()
        self._quarter = 1
        self._closed = False

    def __iter__(self) -> Iterator:
        if self.iterable is None:
            raise TypeError("a progress made without an iterable is advanced by update(), "
                            "not iterated")
        for item in self.iterable:
            yield item
            self.update()
        self.close()

    def update(self, n: int = 1) -> None:
        self.n += n
        crossed = False  # one line however many quarters one update crosses
        while self.total and self._quarter < 4 and 4 * self.n >= self._quarter * self.total:
            self._quarter, crossed = self._quarter + 1, True
        if crossed and self.total and self.n < self.total:  # the end has close()'s line
            self._say(f"{self.n}/{plural(self.total, self.unit)} ({100 * self.n // self.total}%), "
                      f"{time.perf_counter() - self._start:.1f} s")

    def close(self) -> None:
        if not self._closed:
            self._closed = True
            self._say(f"{plural(self.n, self.unit)} in {time.perf_counter() - self._start:.1f} s")

    def _say(self, text: str) -> None:
        if not self.quiet:
            print(f"{self.desc}: {text}" if self.desc else text, file=self.file, flush=True)

    def __enter__(self) -> LogProgress:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def plural(n: int, noun: str) -> str:
    """``"1 job"``, ``"2 jobs"``: a count with its noun (English's regular plural).

    >>> plural(1, "minute"), plural(0, "finished job")
    ('1 minute', '0 finished jobs')
    """
    return f"{n} {noun}" if n == 1 else f"{n} {noun}s"
