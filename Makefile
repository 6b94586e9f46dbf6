# Two commands for a fresh clone: `make demo` (the main job) and `make test`.
# Everything goes into .venv; torch is pinned first so pip takes the CPU build, not CUDA.
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
PIP := $(PY) -m pip
export MUJOCO_GL ?= egl

.PHONY: demo test lint bench-env clean

$(VENV)/.installed: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PIP) install --quiet --upgrade pip
	$(PIP) install --quiet torch==2.13.0
	$(PIP) install --quiet -e ".[train,surf,dev]"
	touch $@

demo: $(VENV)/.installed
	$(VENV)/bin/placeclust demo --out runs/demo

test: $(VENV)/.installed
	$(PY) -m ruff check .
	$(PY) -m pytest -q

bench-env: $(VENV)/.installed
	$(PY) -m envs.benchmark

clean:
	rm -rf $(VENV) runs .pytest_cache .ruff_cache
