"""Atomic file writes: a reader, or a process killed mid-write, sees the old file or the new one.

Map files (:mod:`placeclust.mapfile`) and the benchmark's run store
(``envs/runs/store.py``) both write this way.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import BinaryIO


def write_atomic(path: str | os.PathLike, write: Callable[[BinaryIO], object]) -> Path:
    """Write ``path`` all at once.

    Args:
        path: the target; its folder must exist. An existing file is replaced only once the
            new one is complete.
        write: fills the open temporary file (binary mode) that becomes ``path``.

    Returns:
        The path written. If ``write`` or the rename fails, the exception propagates, the old
        file is untouched and no temporary file is left.

    Examples:
        >>> import tempfile
        >>> from pathlib import Path
        >>> from placeclust.atomic import write_atomic
        >>> with tempfile.TemporaryDirectory() as folder:
        ...     path = write_atomic(Path(folder) / "note.txt", lambda f: f.write(b"hello"))
        ...     print(path.read_bytes(), sorted(p.name for p in Path(folder).iterdir()))
        b'hello' ['note.txt']
    """
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as f:
            write(f)
            f.flush()
            os.fsync(f.fileno())
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # mkstemp makes it private; ours is an ordinary file
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path
