# Two commands for a fresh clone: `make demo` (the main job) and `make test`.
# Everything goes into .venv; torch is pinned first so pip takes the CPU build, not CUDA.
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
PIP := $(PY) -m pip
export MUJOCO_GL ?= egl

.PHONY: demo test benchmarks bench bench-quick bench-long bench-env bench-latency train eval \
	leaderboard train-errands train-tour agents-tour seed001 clean

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
	$(PY) -m mypy
	$(PY) -m pytest -q

# Regenerates every table of docs/benchmarks.md, one command after the other (never two timings
# at once): about 3.5 hours on a 2-core machine, the full closed-loop suite 106 minutes of it.
DOCS := --docs docs/benchmarks.md
PANORAMA_TOURS := --algos online --features sift --conditions day --scenes 0 1 2 3 --rooms 4 8 \
	--tour-seeds 0 1 --steps-per-room 150 --latency-sizes
# PANORAMA with SIFT and ORB on 24 tours of a split's first 4 scenes: 4, 8, 12 rooms x 2 tour seeds
SPLIT_TOURS := --preset panorama --algos online --features sift orb --conditions day \
	--rooms 4 8 12 --tour-seeds 0 1 --steps-per-room 150 --latency-sizes
# PANORAMA_ORB on the same 24 tours of a split
ORB_TOURS := --preset panorama-orb --algos online --features orb --conditions day --rooms 4 8 12 \
	--tour-seeds 0 1 --steps-per-room 150 --latency-sizes
# the offline baselines given as many places as rooms, or as the online recognizer opened
MATCHED := --algos kmeans wpgma kunion --conditions day --latency-sizes
benchmarks: $(VENV)/.installed
	$(VENV)/bin/placeclust demo --out runs/demo $(DOCS)
	$(VENV)/bin/placeclust bench $(PANORAMA_TOURS) --param view=sides --param kernel_capacity=600 \
		--param scene_change=0.25 --param scale=0.75 --out runs/panorama $(DOCS)
	$(VENV)/bin/placeclust bench $(PANORAMA_TOURS) --out runs/defaults $(DOCS)
	$(VENV)/bin/placeclust bench --quick $(DOCS)
	$(VENV)/bin/placeclust bench --quick $(MATCHED) --param n_clusters=rooms --out runs/matched-rooms $(DOCS)
	$(VENV)/bin/placeclust bench --quick $(MATCHED) --param n_clusters=online --out runs/matched-online $(DOCS)
	$(VENV)/bin/placeclust bench $(SPLIT_TOURS) --split test --out runs/panorama-test $(DOCS)
	$(VENV)/bin/placeclust bench $(SPLIT_TOURS) --split train --out runs/panorama-train $(DOCS)
	$(VENV)/bin/placeclust bench $(ORB_TOURS) --split test --out runs/panorama-orb-test $(DOCS)
	$(VENV)/bin/placeclust bench $(ORB_TOURS) --split train --out runs/panorama-orb-train $(DOCS)
	$(VENV)/bin/placeclust bench --preset panorama --algos online --features sift --conditions day \
		--rooms 4 8 12 --tour-seeds 0 1 --steps-per-room 250 --latency-sizes --split test \
		--out runs/panorama-test-250 $(DOCS)
	$(VENV)/bin/placeclust seed001 --split test --rooms 6 --workers 2 $(DOCS) --section seed001-test
	$(VENV)/bin/placeclust seed001 --split test --rooms 6 --workers 2 --param min_matches=250 $(DOCS) \
		--section seed001-test-250
	$(VENV)/bin/placeclust latency $(DOCS)
	$(VENV)/bin/placeclust latency --param consolidate=0.85 --section latency-consolidate \
		$(DOCS)
	$(VENV)/bin/placeclust latency --features orb --param view=sides \
		--param kernel_capacity=600 --param scene_change=0.12 --param scale=0.75 \
		--param consolidate=0.85 --param t_new_cluster=0.94 --section latency-panorama-orb $(DOCS)
	$(VENV)/bin/placeclust speed $(DOCS)
	$(PY) -m train.evaluate --agent all --episodes 50 --seed 1000 $(DOCS)
	$(PY) -m train.evaluate --agent all --episodes 50 --seed 1000 $(DOCS) \
		--config train/hyperparams/ppo_proximity.yml --policies assets/policies/proximity
	$(PY) -m train.evaluate --agent all --episodes 50 --seed 1000 $(DOCS) \
		--config train/hyperparams/ppo_corridor.yml --policies assets/policies/corridor
	$(VENV)/bin/placeclust leaderboard --split val --n-scenes 8 --goals-per-scene 5 \
		--recognizers oracle panorama panorama-orb random --out runs/pilot-val $(DOCS)
	$(VENV)/bin/placeclust leaderboard --suite placenav-v1 --size quick --out runs/quick $(DOCS)
	$(VENV)/bin/placeclust compare runs/quick/results.json runs/quick/results.json \
		--a panorama --b panorama-orb $(DOCS)
	$(VENV)/bin/placeclust leaderboard --suite placenav-v1 --size quick \
		--recognizers oracle panorama panorama-orb --agent ppo --out runs/quick-ppo $(DOCS)
	$(VENV)/bin/placeclust leaderboard --suite placenav-v1 --out runs/leaderboard $(DOCS)
	$(VENV)/bin/placeclust compare runs/leaderboard/results.json runs/leaderboard/results.json \
		--a panorama --b panorama-orb $(DOCS) --section compare-placenav-v1
	$(VENV)/bin/placeclust leaderboard --suite placenav-v1 --size long --out runs/long $(DOCS)
	for r in panorama panorama-orb; do $(VENV)/bin/placeclust compare runs/long/results.json \
		runs/quick/results.json --a $$r --b $$r --force $(DOCS) --section compare-long-quick-$$r; done

# the benchmark matrix (envs/commands/bench.py): results.csv, results.md, precision.png, latency.png
bench-quick: $(VENV)/.installed
	$(VENV)/bin/placeclust bench --quick

bench: $(VENV)/.installed
	$(VENV)/bin/placeclust bench

# 20,000 steps in a 12-room world with the online recognizer in the loop
bench-long: $(VENV)/.installed
	$(VENV)/bin/placeclust longrun --steps 20000 --rooms 12

bench-env: $(VENV)/.installed
	$(VENV)/bin/placeclust speed

bench-latency: $(VENV)/.installed
	$(VENV)/bin/placeclust latency

# reproduces assets/policies/ppo_place.zip (the other agents: --agent noplace / oracle)
train: $(VENV)/.installed
	$(PY) -m train.train --agent place --seed 0 --map assets/policies

eval: $(VENV)/.installed
	$(PY) -m train.evaluate --agent all --episodes 50 --seed 1000

# recognizers ranked by errand success on the frozen suite's test buildings (hours: see
# docs/benchmarks.md for the cost; --size quick for a check)
leaderboard: $(VENV)/.installed
	$(VENV)/bin/placeclust leaderboard --suite placenav-v1 --out runs/leaderboard

# seed 001 on its paper's camera: Tables 2-3 and a second drive, 4 test buildings (~3 min)
seed001: $(VENV)/.installed
	$(VENV)/bin/placeclust seed001 --split test --rooms 6 --workers 2

# reproduces assets/policies/errands/ppo_errands.zip, the learned errand agent
train-errands: $(VENV)/.installed
	$(PY) -m train.train --agent errands --config train/hyperparams/ppo_errands.yml \
		--out runs/train/errands_s0

# errand agents on their own in buildings never seen (envs/agents/tour_features.py), carried to
# each errand's start: each trains on train buildings in 5 (PPO) to 13 (LSTM) minutes on 2 cores
TOUR_AGENTS := noplace place oracle noplace_lstm place_lstm
train-tour: $(VENV)/.installed
	for a in $(TOUR_AGENTS); do \
		$(PY) -m train.train --agent $$a --config train/hyperparams/ppo_tour_carried.yml \
			--out runs/train/carried_$$a --no-progress || exit 1; done

# and scores them on test buildings, paired, beside the planner on the same maps (~35 minutes):
# the shipped policies, or yours after make train-tour with TOUR_POLICIES=runs/train; the
# memory baselines are not shipped (8 MB each): make train-tour first
TOUR_POLICIES ?= assets/policies/tour
LSTM_POLICIES ?= runs/train
AGENT_ERRANDS := --split test --n-scenes 20 --rooms 6 --goals-per-scene 5 --workers 2 \
	--errand-start carried --out runs/agents/carried
agents-tour: $(VENV)/.installed
	$(VENV)/bin/placeclust errands $(AGENT_ERRANDS) --recognizer none --agent ppo \
		--policy $(TOUR_POLICIES)/carried_noplace/policy.zip --json runs/agents/carried-noplace.json
	for a in place oracle; do $(VENV)/bin/placeclust errands $(AGENT_ERRANDS) \
		--recognizer panorama-orb --agent ppo --policy $(TOUR_POLICIES)/carried_$$a/policy.zip \
		--json runs/agents/carried-$$a.json || exit 1; done
	$(VENV)/bin/placeclust errands $(AGENT_ERRANDS) --recognizer oracle --agent ppo \
		--policy $(TOUR_POLICIES)/carried_place/policy.zip --json runs/agents/carried-place-true.json
	$(VENV)/bin/placeclust errands $(AGENT_ERRANDS) --recognizer panorama-orb --agent planner \
		--json runs/agents/carried-planner.json
	$(VENV)/bin/placeclust errands $(AGENT_ERRANDS) --recognizer none --agent ppo \
		--policy $(LSTM_POLICIES)/carried_noplace_lstm/policy.zip \
		--json runs/agents/carried-noplace_lstm.json
	$(VENV)/bin/placeclust errands $(AGENT_ERRANDS) --recognizer oracle --agent ppo \
		--policy $(LSTM_POLICIES)/carried_place_lstm/policy.zip \
		--json runs/agents/carried-place_lstm-true.json
	$(VENV)/bin/placeclust compare runs/agents/carried-place.json \
		runs/agents/carried-noplace.json $(DOCS) --section agents-carried-place-noplace
	$(VENV)/bin/placeclust compare runs/agents/carried-oracle.json \
		runs/agents/carried-place.json $(DOCS) --section agents-carried-oracle-place
	$(VENV)/bin/placeclust compare runs/agents/carried-place-true.json \
		runs/agents/carried-place.json $(DOCS) --section agents-carried-place-recognition
	$(VENV)/bin/placeclust compare runs/agents/carried-place.json \
		runs/agents/carried-planner.json $(DOCS) --section agents-carried-place-planner
	$(VENV)/bin/placeclust compare runs/agents/carried-noplace_lstm.json \
		runs/agents/carried-noplace.json $(DOCS) --section agents-carried-memory-noplace
	$(VENV)/bin/placeclust compare runs/agents/carried-place_lstm-true.json \
		runs/agents/carried-place-true.json $(DOCS) --section agents-carried-memory-place

clean:
	rm -rf $(VENV) runs .pytest_cache .ruff_cache
