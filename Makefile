# Two commands for a fresh clone: `make demo` (the main job) and `make test`.
# Everything goes into .venv; torch is pinned first so pip takes the CPU build, not CUDA.
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
PIP := $(PY) -m pip
export MUJOCO_GL ?= egl

.PHONY: demo test pin test-oldest docs-check docs-verify real-images benchmarks bench bench-quick bench-long bench-env bench-latency train eval \
	renderers leaderboard leaderboard-v1 leaderboard-v3 leaderboard-v4 leaderboard-v5 leaderboard-v5-companions train-errands train-tour train-reachroom agents-tour agents-suite seed001 \
	clean

$(VENV)/.installed: pyproject.toml constraints.txt
	$(PYTHON) -m venv $(VENV)
	$(PIP) install --quiet --upgrade pip
	$(PIP) install --quiet -c constraints.txt torch
	$(PIP) install --quiet -c constraints.txt -e ".[train,surf,ray,dev]"
	touch $@

# constraints.txt from .venv: the pinned benchmark environment (upgrade a library, then pin)
pin:
	sed -n '/^#/p' constraints.txt > constraints.txt.new
	$(PIP) freeze --exclude-editable | sed 's/+cpu$$//' >> constraints.txt.new
	mv constraints.txt.new constraints.txt

demo: $(VENV)/.installed
	$(VENV)/bin/placeclust demo --out runs/demo

# the tests in parallel, a file per worker (its module fixtures built once): about half the time
# on CI's 2 cores; at most 4 workers, as each loads MuJoCo and torch
test: $(VENV)/.installed
	$(PY) -m ruff check .
	$(PY) -m mypy
	$(PY) -m pytest -q -n auto --maxprocesses 4 --dist loadfile

# The library and simulator tests on the oldest dependencies pyproject.toml allows
# (tests/oldest.txt), in a venv of their own; of the train extra only pyyaml (the closed loop's
# tests read its configs), so the tests that need stable-baselines3 skip.
OLDEST := .venv-oldest
$(OLDEST)/.installed: pyproject.toml tests/oldest.txt
	$(PYTHON) -m venv $(OLDEST)
	$(OLDEST)/bin/python -m pip install --quiet --upgrade pip
	$(OLDEST)/bin/python -m pip install --quiet -c tests/oldest.txt -r tests/oldest.txt \
		pyyaml pytest pytest-xdist hypothesis
	touch $@

test-oldest: $(OLDEST)/.installed
	PYTHONPATH=. $(OLDEST)/bin/python -m pytest -q -n auto --maxprocesses 4 --dist loadfile \
		-p no:cacheprovider tests/placeclust tests/envs tests/test_examples.py

# Whether the tables claims cite (docs/freshness/cited.py) are what today's code measures
# (docs.freshness; make test fails on a cited one whose code moved, until verified or measured)
docs-check: $(VENV)/.installed
	$(PY) -m docs.freshness check

# Runs the probe of every section whose code moved, with the code that measured it and with
# today's, and lists those that differ (docs/design.md, "Which tables must be current"; the
# cited sections took about two hours on 2 cores)
docs-verify: $(VENV)/.installed
	$(PY) -m docs.freshness verify

# The real corridor data set (shared/data, beside the clone) beside 4 val buildings, and the image
# statistics of simulated forward tours with and without doors: about 10 minutes
CORRIDOR := ../shared/data/vpr-bench-corridor
real-images: $(VENV)/.installed
	$(VENV)/bin/placeclust bench --quick --dataset $(CORRIDOR) --scenes 1000 1001 1002 1003 \
		--conditions day --algos online nested --features sift kaze orb akaze --latency-sizes \
		--out runs/corridor $(DOCS)
	for s in 1000 2000; do for d in "" "--doors 1.0"; do $(VENV)/bin/placeclust tour \
		--scene-seed $$s --rooms 6 --steps 900 --camera forward $$d --quiet \
		--out runs/stats/forward-$$s$${d:+-doors}; done; done
	$(VENV)/bin/placeclust tour --scene-seed 1000 --rooms 6 --steps 900 --quiet \
		--out runs/stats/panorama-1000
	$(VENV)/bin/placeclust stats --images $(CORRIDOR) --tour runs/stats/forward-2000/tour.npz \
		runs/stats/forward-2000-doors/tour.npz runs/stats/forward-1000/tour.npz \
		runs/stats/forward-1000-doors/tour.npz runs/stats/panorama-1000/tour.npz $(DOCS) \
		--section image-stats
	$(VENV)/bin/placeclust stats --images $(CORRIDOR) --tour runs/stats/forward-2000/tour.npz \
		runs/stats/forward-2000-doors/tour.npz runs/stats/forward-1000/tour.npz \
		runs/stats/forward-1000-doors/tour.npz --max-features 100 $(DOCS) --section image-stats-100

# Regenerates every table of docs/benchmarks.md but the tracks' val pilots (their commands are in
# the docs), one command after the other (never two timings at once): about 9 hours on a 2-core
# machine by its speed that day (before 0.17.0 retired 13 tables to docs/retired.md), the suites
# 55 to 106 minutes (v1) and 1 h 45 min to 3.5 hours (v2), v2's calibration 43 minutes.
DOCS := --docs docs/benchmarks.md
# the sections of the tracks' val pilots, which make benchmarks does not run (so does not record)
VAL_PILOTS := score-pilot-val score-pilot-lit-val leaderboard-val-corridor-carried-relocalizer \
	compare-val-corridor-carried calibration-corridor-carried-val calibration-tracks-val \
	$(foreach t,continued changed-night changed-moved carried corridor corridor-carried,\
	leaderboard-val-$(t)-spot) score-pilot-v3-val
# seed 000's recognizer with the paper's values (--preset paper), as a user's class
PAPER := placeclust.online:OnlinePlaceClustering
# the closed loop's tracks (envs.runs.suite.TRACKS), as v2 to v4 run them
TRACKS := continued changed-night changed-cloudy changed-moved carried corridor \
	corridor-carried long
V2_TRACKS := $(foreach t,$(TRACKS),runs/v2/$(t)/results.json)
# PANORAMA with SIFT and ORB on 24 tours of a split's first 4 scenes: 4, 8, 12 rooms x 2 tour seeds
SPLIT_TOURS := --preset panorama --algos online --features sift orb --conditions day \
	--rooms 4 8 12 --tour-seeds 0 1 --steps-per-room 150 --latency-sizes
# PANORAMA_ORB on the same 24 tours of a split
ORB_TOURS := --preset panorama-orb --algos online --features orb --conditions day --rooms 4 8 12 \
	--tour-seeds 0 1 --steps-per-room 150 --latency-sizes
# the offline baselines given as many places as rooms, or as the online recognizer opened
MATCHED := --algos kmeans wpgma kunion --conditions day --latency-sizes
# The renderer's part of the figures (docs.renderers): llvmpipe as this CPU draws it and limited
# to SSE4.1 at 128 bits, as on a CPU without AVX; the demo, the README's open-loop test tours and
# placenav-v4's best real recognizer (the native rows: its shipped store). ~1 h 15 min on 2 cores.
RENDER_OUT := runs/renderers
SSE41 := GALLIUM_OVERRIDE_CPU_CAPS=sse4.1
renderers: $(VENV)/.installed
	$(VENV)/bin/placeclust demo --out $(RENDER_OUT)/native/demo
	$(SSE41) $(VENV)/bin/placeclust demo --out $(RENDER_OUT)/sse41/demo
	$(VENV)/bin/placeclust bench $(SPLIT_TOURS:--latency-sizes=) --split test \
		--out $(RENDER_OUT)/native/bench
	$(SSE41) $(VENV)/bin/placeclust bench $(SPLIT_TOURS:--latency-sizes=) --split test \
		--out $(RENDER_OUT)/sse41/bench
	$(SSE41) $(VENV)/bin/placeclust leaderboard --suite placenav-v4 --recognizers panorama-orb \
		--out $(RENDER_OUT)/sse41/placenav-v4
	$(PY) -m docs.renderers $(RENDER_OUT) --store docs/runs/placenav-v4 --docs docs/rendering.md

benchmarks: $(VENV)/.installed
	$(VENV)/bin/placeclust demo --out runs/demo $(DOCS)
	$(VENV)/bin/placeclust bench --quick $(MATCHED) --param n_clusters=rooms --out runs/matched-rooms $(DOCS)
	$(VENV)/bin/placeclust bench --quick $(MATCHED) --param n_clusters=online --out runs/matched-online $(DOCS)
	$(VENV)/bin/placeclust bench $(SPLIT_TOURS) --split test --out runs/panorama-test $(DOCS)
	$(VENV)/bin/placeclust bench $(SPLIT_TOURS) --split train --out runs/panorama-train $(DOCS)
	$(VENV)/bin/placeclust bench $(ORB_TOURS) --split test --out runs/panorama-orb-test $(DOCS)
	$(VENV)/bin/placeclust bench $(ORB_TOURS) --split train --out runs/panorama-orb-train $(DOCS)
	$(VENV)/bin/placeclust seed001 --split test --rooms 6 --workers 2 $(DOCS) --section seed001-test
	$(VENV)/bin/placeclust seed001 --split test --rooms 6 --workers 2 --param min_matches=250 $(DOCS) \
		--section seed001-test-250
	$(VENV)/bin/placeclust seed001 --split test --rooms 6 --workers 2 --doors 1.0 $(DOCS) \
		--section seed001-test-doors
	$(VENV)/bin/placeclust seed001 --split test --rooms 6 --workers 2 --doors 1.0 \
		--param max_features=100 $(DOCS) --section seed001-test-doors-100
	$(VENV)/bin/placeclust bench $(SPLIT_TOURS:orb=) --split test --doors 1.0 \
		--out runs/panorama-test-doors $(DOCS)
	for p in panorama paper; do $(VENV)/bin/placeclust bench --preset $$p --algos online \
		--features sift --split val --rooms 6 --tour-seeds 0 --conditions day 'day>day' \
		'day>night' 'day>cloudy' 'day>moved' --local-light --latency-sizes --out runs/lit-$$p \
		--workers 2 $(DOCS); done
	$(MAKE) real-images
	$(VENV)/bin/placeclust speed $(DOCS)
	$(MAKE) agents-tour
	$(VENV)/bin/placeclust leaderboard --split val --n-scenes 8 --errands 5 \
		--recognizers oracle panorama panorama-orb random --out runs/pilot-val $(DOCS)
	$(VENV)/bin/placeclust leaderboard --suite placenav-v1 --out runs/leaderboard $(DOCS)
	$(VENV)/bin/placeclust compare runs/leaderboard/results.json runs/leaderboard/results.json \
		--a panorama --b panorama-orb $(DOCS) --section compare-placenav-v1
	$(MAKE) agents-suite
	$(VENV)/bin/placeclust leaderboard --suite placenav-v2 --size quick --out runs/v2-quick
	$(VENV)/bin/placeclust score $(subst runs/v2/,runs/v2-quick/,$(V2_TRACKS)) $(DOCS) \
		--section score-placenav-v2-quick
	$(VENV)/bin/placeclust leaderboard --suite placenav-v2 --out runs/v2 $(DOCS)
	$(VENV)/bin/placeclust score $(V2_TRACKS) --pair panorama panorama-orb $(DOCS) \
		--section score-placenav-v2
	$(VENV)/bin/placeclust leaderboard --suite placenav-v2 --recognizers $(PAPER) panorama \
		oracle none --preset paper --out runs/v2-paper
	$(VENV)/bin/placeclust score $(subst runs/v2/,runs/v2-paper/,$(V2_TRACKS)) \
		--pair $(PAPER) panorama $(DOCS) --section score-placenav-v2-paper
	$(VENV)/bin/placeclust leaderboard --suite placenav-v2 --recognizers oracle none \
		oracle-noise:0.01 oracle-noise:0.02 oracle-noise:0.05 oracle-merge:0.1 oracle-merge:0.3 \
		oracle-split:2 oracle-split:4 --out runs/v2-cal
	$(VENV)/bin/placeclust score $(subst runs/v2/,runs/v2-cal/,$(V2_TRACKS)) \
		--calibration docs/images/calibration_test.png $(DOCS) --section calibration-placenav-v2
	$(PY) -m docs.freshness record --now $$($(PY) -c "from docs import freshness; \
		print(*sorted(set(freshness.sections()) - set('$(VAL_PILOTS)'.split())))")
	$(PY) -m docs.freshness check --write

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

# reproduces the shipped errand agents, assets/policies/tour/*: trained on train buildings,
# chosen on val (make train-tour), copied with their config, budget and val choice
SHIPPED_TOUR := carried_noplace carried_place carried_oracle continued_noplace continued_place \
	continued_oracle continued_noplace_s1 continued_place_s1 continued_oracle_s1
train: train-tour
	for a in $(SHIPPED_TOUR); do mkdir -p assets/policies/tour/$$a && \
		for f in best_model.zip config.yml train_info.json choice.json; do \
			cp runs/train/$$a/$$f assets/policies/tour/$$a/ || exit 1; done; done

# the single-building PlaceNav-ReachRoom-v0 tutorial: assets/policies/ppo_place.zip (the other
# agents: --agent noplace / oracle) and their table
train-reachroom: $(VENV)/.installed
	$(PY) -m train.train --agent place --seed 0 --map assets/policies

eval: $(VENV)/.installed
	$(PY) -m train.evaluate --agent all --episodes 50 --seed 1000

# recognizers ranked on the frozen suite's eight tracks, test buildings, then one suite score
# (1 h 45 min to 3.5 hours on 2 cores, by the day: docs/benchmarks.md; --size quick to check)
leaderboard: $(VENV)/.installed
	$(VENV)/bin/placeclust leaderboard --suite placenav-v2 --out runs/v2
	$(VENV)/bin/placeclust score $(V2_TRACKS) --pair panorama panorama-orb

# errands to pictures of spots: every built-in, the ceiling and the calibration oracles on
# every track (5.8 core-hours measured, about 3 hours on 2 cores; PANORAMA is 43% of it:
# docs/benchmarks.md, "placenav-v3 at full size")
IMAGE_GOALS := oracle-pose oracle oracle-cells:2 oracle-cells:4 oracle-door:1 \
	oracle-revisit:0.5 panorama panorama-orb nested none random
IMAGE_PAIRS := --ceiling oracle-pose --pair panorama panorama-orb --pair oracle oracle-cells:2 \
	--pair nested none
V3_TRACKS := $(foreach t,$(TRACKS),runs/v3/$(t)/results.json)
leaderboard-v3: $(VENV)/.installed
	$(VENV)/bin/placeclust leaderboard --suite placenav-v3 --out runs/v3 --recognizers $(IMAGE_GOALS)
	$(VENV)/bin/placeclust score $(V3_TRACKS) $(IMAGE_PAIRS)

# v3 with 15 errands a building, which resolve one place a room on most tracks: every built-in,
# the ceiling, true rooms and compact cells (the two error models were told from the ceiling on
# every v3 track; more errands only narrow that). 5.2 core-hours by its rows, 2 h 42 min of 2
# cores by the wall (docs/benchmarks.md, "placenav-v4 at full size"), so its store is kept in
# the repository (docs/runs/placenav-v4): a run reuses the jobs it holds and runs the rest
V4_OUT := docs/runs/placenav-v4
V4_TRACKS := $(foreach t,$(TRACKS),$(V4_OUT)/$(t)/results.json)
leaderboard-v4: $(VENV)/.installed
	$(VENV)/bin/placeclust leaderboard --suite placenav-v4 --out $(V4_OUT) --recognizers \
		$(filter-out oracle-door:1 oracle-revisit:0.5,$(IMAGE_GOALS))
	$(VENV)/bin/placeclust score $(V4_TRACKS) $(IMAGE_PAIRS)

# placenav-v5 (envs/runs/suite_v5.py): every built-in, the ceiling, true rooms and compact cells
# on v4's tracks and the changed tracks on a fixed map, 10 test buildings (long 3), 15 errands:
# sized on val to fit 3 hours of 2 cores (docs/design.md, "placenav-v5"). Its store is kept in
# the repository as v4's; the score's pairs and where success was lost go to the docs
V5_OUT := docs/runs/placenav-v5
V5_TRACKS := $(foreach t,$(TRACKS) changed-night-fixed changed-cloudy-fixed changed-moved-fixed,\
	$(V5_OUT)/$(t)/results.json)
leaderboard-v5: $(VENV)/.installed
	$(VENV)/bin/placeclust leaderboard --suite placenav-v5 --out $(V5_OUT) --recognizers \
		$(filter-out oracle-door:1 oracle-revisit:0.5,$(IMAGE_GOALS)) $(DOCS)
	$(VENV)/bin/placeclust score $(V5_TRACKS) $(IMAGE_PAIRS) --pair panorama random \
		--pair panorama-orb random --decompose $(DOCS) --section score-placenav-v5

# v5's companions: seed 000's values beside PANORAMA (whose kept jobs, with the ceiling's and
# none's, are copied from v5's store: the same jobs, not run again), and seed 001 at 100
# keypoints in v5's buildings with doors
leaderboard-v5-companions: $(VENV)/.installed
	mkdir -p $(V5_OUT)-paper/runs
	cp $(foreach r,panorama oracle-pose none,$(V5_OUT)/runs/$(r)-spot-memory-*.json) \
		$(V5_OUT)-paper/runs/
	$(VENV)/bin/placeclust leaderboard --suite placenav-v5 --out $(V5_OUT)-paper \
		--recognizers oracle-pose none panorama $(PAPER) --preset paper
	$(VENV)/bin/placeclust score $(subst $(V5_OUT)/,$(V5_OUT)-paper/,$(V5_TRACKS)) \
		--ceiling oracle-pose --pair $(PAPER) panorama --decompose $(DOCS) \
		--section score-placenav-v5-paper
	$(VENV)/bin/placeclust leaderboard --suite placenav-v5 --doors 1.0 --out $(V5_OUT)-doors \
		--recognizers oracle-pose none placeclust.nested:NestedMapper --param max_features=100
	$(VENV)/bin/placeclust score $(subst $(V5_OUT)/,$(V5_OUT)-doors/,$(V5_TRACKS)) \
		--ceiling oracle-pose --pair placeclust.nested:NestedMapper none --decompose $(DOCS) \
		--section score-placenav-v5-doors-nested

# the first suite, one set of errands on 60 buildings (55 minutes to 2 hours on 2 cores,
# by the day)
leaderboard-v1: $(VENV)/.installed
	$(VENV)/bin/placeclust leaderboard --suite placenav-v1 --out runs/leaderboard

# seed 001 on its paper's camera: Tables 2-3 and a second drive, 4 test buildings (~3 min)
seed001: $(VENV)/.installed
	$(VENV)/bin/placeclust seed001 --split test --rooms 6 --workers 2

# reproduces assets/policies/errands/ppo_errands.zip, the learned errand agent
train-errands: $(VENV)/.installed
	$(PY) -m train.train --agent errands --config train/hyperparams/ppo_errands.yml \
		--out runs/train/errands_s0

# errand agents on their own in buildings never seen (envs/agents/tour_features.py), for each
# task: carried to each errand's start (grid and corridor buildings) and continued from the tour
# (grid). Each trains in 6 (PPO) to 15 (LSTM) minutes on 2 cores, then its policy is chosen among
# its checkpoints on val (best_model.zip); the continued PPO agents are trained with a second
# seed too (their table resamples the two as seeds): about 3.5 hours in all
TOUR_AGENTS := noplace place oracle noplace_lstm place_lstm
TOUR_TASKS := carried:ppo_tour_carried continued:ppo_tour
SEED1_AGENTS := noplace place oracle
train-tour: $(VENV)/.installed
	for t in $(TOUR_TASKS); do for a in $(TOUR_AGENTS); do run=runs/train/$${t%%:*}_$$a; \
		$(PY) -m train.train --agent $$a --config train/hyperparams/$${t#*:}.yml \
			--out $$run --no-progress && \
		$(PY) -m train.choose $$run --workers 2 --no-progress || exit 1; done; done
	for a in $(SEED1_AGENTS); do run=runs/train/continued_$${a}_s1; \
		$(PY) -m train.train --agent $$a --seed 1 --config train/hyperparams/ppo_tour.yml \
			--out $$run --no-progress && \
		$(PY) -m train.choose $$run --workers 2 --no-progress || exit 1; done

# and scores them on 20 test buildings of each layout, paired (~40 minutes): the shipped
# policies, or yours after make train-tour with TOUR_POLICIES=runs/train; the memory baselines
# are not shipped (8 MB each): make train-tour first. NAME:RECOGNIZER:POLICY; oracle and
# place_true see the true rooms, place and place_lstm a PANORAMA_ORB map of the tour
TOUR_POLICIES ?= assets/policies/tour
LSTM_POLICIES ?= runs/train
TOUR_RUNS := noplace:none:noplace noplace_lstm:none:noplace_lstm \
	place:panorama-orb:place place_lstm:oracle:place_lstm place_true:oracle:place \
	oracle:oracle:oracle
AGENT_ERRANDS := --split test --n-scenes 20 --rooms 6 --errands 5 --workers 2 \
	--errand-start carried --agent ppo
agents-tour: $(VENV)/.installed
	for l in grid corridor; do for run in $(TOUR_RUNS); do \
		name=$${run%%:*}; rest=$${run#*:}; rec=$${rest%%:*}; pol=$${rest#*:}; \
		case $$pol in *_lstm) dir=$(LSTM_POLICIES);; *) dir=$(TOUR_POLICIES);; esac; \
		$(VENV)/bin/placeclust errands $(AGENT_ERRANDS) --layout $$l --recognizer $$rec \
			--policy $$dir/carried_$$pol/best_model.zip --out runs/agents/$$l \
			--json runs/agents/$$l/$$name.json || exit 1; done; \
		$(PY) -m train.report $(foreach r,$(TOUR_RUNS),$(firstword $(subst :, ,$(r)))=runs/agents/$$l/$(firstword $(subst :, ,$(r))).json) \
			--against oracle noplace noplace_lstm $(DOCS) --section agents-carried-$$l || exit 1; done

# the agents of errands continued from the tour on the suite's leaderboard (60 test buildings):
# the five trained on them (the PPO ones with their two seeds), place also on a PANORAMA_ORB map,
# and the carried noplace and place agents, in one paired table (about 2 hours, 70 minutes of it
# PANORAMA_ORB); continued place paired with the planner on the same maps (make leaderboard);
# and how far the PPO agents' dead reckoning drifts on 6 val buildings (train.drift, 3 minutes).
# NAME:RECOGNIZERS:POLICY
SUITE_RUNS := noplace:none:continued_noplace noplace_s1:none:continued_noplace_s1 \
	noplace_lstm:none:continued_noplace_lstm place:oracle,panorama-orb:continued_place \
	place_s1:oracle,panorama-orb:continued_place_s1 place_lstm:oracle:continued_place_lstm \
	oracle:oracle:continued_oracle oracle_s1:oracle:continued_oracle_s1 \
	carried_noplace:none:carried_noplace carried_place:oracle:carried_place
# NAME:RUN[+RUN]:RECOGNIZER, a row of the table (runs joined by + are one agent's seeds):
# place_true is the place agent on the true rooms
SUITE_ROWS := noplace:noplace+noplace_s1:none noplace_lstm:noplace_lstm:none \
	place:place+place_s1:panorama-orb place_true:place+place_s1:oracle \
	place_lstm:place_lstm:oracle oracle:oracle+oracle_s1:oracle \
	carried_noplace:carried_noplace:none carried_place_true:carried_place:oracle
empty :=
space := $(empty) $(empty)
comma := ,
suite_row = $(word 1,$(subst :, ,$(1)))=$(subst $(space),$(comma),$(foreach run,$(subst +, ,$(word 2,$(subst :, ,$(1)))),runs/suite/$(run)/results.json@$(word 3,$(subst :, ,$(1)))))
agents-suite: $(VENV)/.installed
	for run in $(SUITE_RUNS); do name=$${run%%:*}; rest=$${run#*:}; recs=$${rest%%:*}; \
		pol=$${rest#*:}; case $$pol in *_lstm) dir=$(LSTM_POLICIES);; *) dir=$(TOUR_POLICIES);; esac; \
		$(VENV)/bin/placeclust leaderboard --suite placenav-v1 --recognizers $$(echo $$recs | tr , ' ') \
			--agent ppo --policy $$dir/$$pol/best_model.zip --out runs/suite/$$name || exit 1; done
	$(PY) -m train.report $(foreach r,$(SUITE_ROWS),$(call suite_row,$(r))) \
		--against oracle noplace noplace_lstm $(DOCS) --section agents-suite-continued
	for r in oracle panorama-orb; do $(VENV)/bin/placeclust compare \
		runs/suite/place/results.json runs/leaderboard/results.json --a $$r --b $$r \
		$(DOCS) --section agents-suite-continued-planner-$$r || exit 1; done
	$(PY) -m train.drift $(foreach a,noplace place oracle,$(TOUR_POLICIES)/continued_$(a)/best_model.zip) \
		$(DOCS) --section agents-drift

clean:
	rm -rf $(VENV) $(OLDEST) runs .pytest_cache .ruff_cache
