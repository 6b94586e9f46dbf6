import os
import subprocess
import sys

import pytest

from placeclust.allocator import is_glibc, keep_frame_buffers, user_has_malloc_settings

glibc = pytest.mark.skipif(not is_glibc(), reason="glibc malloc only")

# Allocates and frees a 2 MB buffer 40 times (a frame's similarity matrix, say) after importing
# placeclust, and prints the page faults that cost: a fresh mapping faults every page each time.
FAULTS = """
import resource, numpy as np, placeclust
np.ones(1 << 18).sum()
before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
for _ in range(40):
    np.ones(1 << 18).sum()
print(resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before)
"""


def page_faults(**env: str) -> int:
    clean = {k: v for k, v in os.environ.items()
             if not k.startswith("MALLOC_") and k != "GLIBC_TUNABLES"}
    out = subprocess.run([sys.executable, "-c", FAULTS], env={**clean, **env}, check=True,
                         capture_output=True, text=True).stdout
    return int(out)


@glibc
def test_importing_placeclust_keeps_large_frame_buffers_mapped():
    pages = 40 * (1 << 21) // 4096
    assert page_faults() < 0.05 * pages
    # the user's own setting wins, and with glibc's default threshold every buffer faults again
    assert page_faults(MALLOC_MMAP_THRESHOLD_="131072") > 0.9 * pages


def test_user_settings_are_recognised_and_left_alone():
    assert not user_has_malloc_settings({})
    assert not user_has_malloc_settings({"GLIBC_TUNABLES": "glibc.pthread.rseq=0"})
    assert user_has_malloc_settings({"MALLOC_TRIM_THRESHOLD_": "0"})
    assert user_has_malloc_settings({"GLIBC_TUNABLES": "glibc.malloc.trim_threshold=1"})
    assert keep_frame_buffers({"MALLOC_ARENA_MAX_": "1", "MALLOC_MMAP_MAX_": "0"}) is False


@glibc
def test_settings_apply_on_glibc_and_can_be_applied_again():
    assert keep_frame_buffers({}) is True
    assert keep_frame_buffers({}) is True
