"""The command line's argument parser: a bad option is one line and exit status 2.

:class:`argparse.ArgumentParser` answers a bad option with the whole usage (18 lines for
``placeclust leaderboard``) above the error, which pushes the one line that matters off a
small terminal. Every ``placeclust`` command and ``train`` script parses with
:class:`ArgumentParser`, which prints only ``PROG: error: MESSAGE (PROG -h lists the
options)``.

Examples:
    >>> from placeclust.argparsing import ArgumentParser
    >>> p = ArgumentParser(prog="demo")
    >>> _ = p.add_argument("--track", choices=["a", "b"])
    >>> try:
    ...     p.parse_args(["--track", "c"])
    ... except SystemExit as exit:
    ...     exit.code
    2
"""

from __future__ import annotations

import argparse
from typing import NoReturn


class ArgumentParser(argparse.ArgumentParser):
    """An :class:`argparse.ArgumentParser` whose errors are one line on standard error
    (exit 2); its subparsers are of the same class."""

    def error(self, message: str) -> NoReturn:
        message = " ".join(message.split())  # argparse may fold a long choice list
        self.exit(2, f"{self.prog}: error: {message} ({self.prog} -h lists the options)\n")

