"""The library is the bottom layer: importing every ``placeclust`` module pulls in neither the
simulator, the training code, gymnasium nor MuJoCo (``docs/design.md``, "Layers")."""

import subprocess
import sys

FORBIDDEN = ("envs", "placeclust_envs", "train", "gymnasium", "mujoco", "stable_baselines3",
             "torch")

CODE = f"""
import importlib, pkgutil, sys
import placeclust
names = [m.name for m in pkgutil.walk_packages(placeclust.__path__, "placeclust.")]
assert len(names) > 10, names
for name in names:
    importlib.import_module(name)
bad = sorted(m for m in sys.modules if m.split(".")[0] in {FORBIDDEN!r})
assert not bad, f"placeclust imported {{bad}}"
print(len(names))
"""


def test_every_placeclust_module_imports_without_the_simulator():
    # a fresh interpreter: this test process has imported the simulator already
    out = subprocess.run([sys.executable, "-c", CODE], check=True, capture_output=True, text=True)
    assert int(out.stdout) > 10
