# Two entry points: `make demo` (plan the regrasp scene, write plan, figure and replay)
# and `make test` (install everything from scratch and run the test suite).
PYTHON ?= python3
VENV   ?= .venv
BIN    := $(VENV)/bin
OUT    ?= out

.PHONY: venv demo test lint figures bench clean

$(BIN)/pivot-ompl: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e ".[dev,dask,talos]"
	touch $@

venv: $(BIN)/pivot-ompl

demo: venv
	mkdir -p $(OUT)
	$(BIN)/pivot-ompl plan scenes/fig10.yaml --planner regrasp --time 60 --seed 0 \
	    --out $(OUT)/fig10_plan.json --plot $(OUT)/fig10_plan.png
	$(BIN)/pivot-ompl check scenes/fig10.yaml $(OUT)/fig10_plan.json
	$(BIN)/pivot-ompl animate $(OUT)/fig10_plan.json --out $(OUT)/fig10_motion.npz
	$(BIN)/pivot-ompl replay $(OUT)/fig10_motion.npz --plan $(OUT)/fig10_plan.json \
	    --scene scenes/fig10.yaml --html $(OUT)/fig10_replay.html
	@echo "replay: $(abspath $(OUT)/fig10_replay.html)"

test: venv
	$(BIN)/python -m pytest -q $(PYTEST_ARGS) tests

lint: venv
	$(BIN)/ruff check pivot_ompl tests benchmarks
	$(BIN)/mypy
	$(BIN)/lint-imports

# The README's table of current figures (about ten minutes on a 2-core machine, one planning
# process at a time): results/figures/figures.md
figures: venv
	PIVOT_BENCH_LOCK=/tmp/pivot-bench.lock $(BIN)/python benchmarks/figures.py --out results/figures

bench: figures

clean:
	rm -rf $(VENV) $(OUT)
