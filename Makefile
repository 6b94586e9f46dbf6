# Two commands for a fresh clone: `make demo` (the main job) and `make test`.
# Everything goes into .venv; torch is pinned first so pip takes the CPU build, not CUDA.
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
PIP := $(PY) -m pip
export MUJOCO_GL ?= egl

.PHONY: demo test bench bench-quick bench-long bench-env bench-latency train eval clean

$(VENV)/.installed: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PIP) install --quiet --upgrade pip
	$(PIP) install --quiet torch==2.13.0
	$(PIP) install --quiet -e ".[train,surf,ray,dev]"
	touch $@

demo: $(VENV)/.installed
	$(VENV)/bin/placeclust demo --out runs/demo

test: $(VENV)/.installed
	$(PY) -m ruff check .
	$(PY) -m pytest -q

# the benchmark matrix (placeclust/bench.py): results.csv, results.md, precision.png, latency.png
bench-quick: $(VENV)/.installed
	$(VENV)/bin/placeclust bench --quick

bench: $(VENV)/.installed
	$(VENV)/bin/placeclust bench

# 20,000 steps in a 12-room world with the online recognizer in the loop
bench-long: $(VENV)/.installed
	$(PY) -m envs.longrun --steps 20000 --rooms 12

bench-env: $(VENV)/.installed
	$(PY) -m envs.benchmark

bench-latency: $(VENV)/.installed
	$(PY) -m placeclust.benchmark latency

# reproduces assets/policies/ppo_place.zip (the other agents: --agent noplace / oracle)
train: $(VENV)/.installed
	$(PY) -m train.train --agent place --seed 0 --map assets/policies

eval: $(VENV)/.installed
	$(PY) -m train.evaluate --agent all --episodes 50 --seed 1000

clean:
	rm -rf $(VENV) runs .pytest_cache .ruff_cache
