"""glibc malloc settings that keep each frame's large buffers in the heap instead of mmap.

Every frame, SIFT builds an image pyramid of ~1 MB float layers (OpenCV doubles a 512x128 frame
to 1024x256 for its first octave) and the matcher a ~2 MB similarity matrix, then frees them.
With glibc's defaults a block over 128 KiB is served by ``mmap`` and freed heap tops over
128 KiB go back to the OS, so these buffers are mapped, page-faulted and zeroed anew each frame,
which slows SIFT detection markedly. glibc raises these thresholds by itself after the first
large ``free`` of an mmapped block; this starts every process there.

The cost is memory the process keeps instead of returning: up to ``TRIM_THRESHOLD`` of free
heap. A user's own ``MALLOC_*_`` environment variables or ``glibc.malloc`` tunables win: then
nothing is changed. Other C libraries (macOS, musl) are left alone.
"""

from __future__ import annotations

import ctypes
import os
from collections.abc import Mapping

M_TRIM_THRESHOLD, M_MMAP_THRESHOLD = -1, -3  # <malloc.h>
#: glibc's own ceiling for its dynamic mmap threshold on 64-bit systems.
MMAP_THRESHOLD = 32 * 1024 * 1024
#: twice the mmap threshold, as glibc's dynamic rule sets it.
TRIM_THRESHOLD = 2 * MMAP_THRESHOLD
_USER_SETTINGS = ("MALLOC_MMAP_THRESHOLD_", "MALLOC_TRIM_THRESHOLD_", "MALLOC_TOP_PAD_",
                  "MALLOC_MMAP_MAX_")


def user_has_malloc_settings(environ: Mapping[str, str] = os.environ) -> bool:
    """Whether ``environ`` sets glibc malloc parameters of its own.

    Examples:
        >>> from placeclust.allocator import user_has_malloc_settings
        >>> user_has_malloc_settings({"GLIBC_TUNABLES": "glibc.malloc.trim_threshold=0"})
        True
        >>> user_has_malloc_settings({})
        False
    """
    return (any(name in environ for name in _USER_SETTINGS)
            or "glibc.malloc." in environ.get("GLIBC_TUNABLES", ""))


def is_glibc() -> bool:
    """Whether this process runs on glibc, asked of the C library itself (no file is read)."""
    try:
        return (os.confstr("CS_GNU_LIBC_VERSION") or "").startswith("glibc")
    except (ValueError, OSError, AttributeError):  # name unknown on this system, or no confstr
        return False


def keep_frame_buffers(environ: Mapping[str, str] = os.environ) -> bool:
    """Raise glibc's mmap and trim thresholds for this process (see the module docstring).

    Returns:
        True if the settings were applied; False on a C library other than glibc or when
        ``environ`` holds the user's own malloc settings.

    Examples:
        The user's own settings win:

        >>> from placeclust.allocator import keep_frame_buffers
        >>> keep_frame_buffers({"MALLOC_MMAP_THRESHOLD_": "131072"})
        False
    """
    if not is_glibc() or user_has_malloc_settings(environ):
        return False
    try:
        mallopt = ctypes.CDLL(None).mallopt
    except (OSError, AttributeError):
        return False
    mallopt.argtypes, mallopt.restype = [ctypes.c_int, ctypes.c_int], ctypes.c_int
    return bool(mallopt(M_MMAP_THRESHOLD, MMAP_THRESHOLD)
                and mallopt(M_TRIM_THRESHOLD, TRIM_THRESHOLD))
