# Two entry points: `make demo` (plan the regrasp scene, write plan, figure and replay)
# and `make test` (install everything from scratch and run the test suite).
PYTHON ?= python3
VENV   ?= .venv
BIN    := $(VENV)/bin
OUT    ?= out

.PHONY: venv demo test lint docs figures bench clean

$(BIN)/pivot-ompl: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e ".[dev,dask,docs,physics,talos]"
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

# Tests in two passes: those that time nothing on every core (at most four workers), then
# the timed ones (`-m timed`: time budgets, clock stops) alone, as a user's machine runs them;
# both passes run, the first failure's status is make's
test: venv
	s1=0; s2=0; \
	$(BIN)/python -m pytest -q $(PYTEST_ARGS) -n auto --maxprocesses 4 -m "not timed" tests \
	    || s1=$$?; \
	$(BIN)/python -m pytest -q $(PYTEST_ARGS) -m timed tests || s2=$$?; \
	if [ $$s1 -ne 0 ]; then exit $$s1; fi; exit $$s2

lint: venv
	$(BIN)/ruff check pivot_ompl tests benchmarks
	$(BIN)/mypy
	$(BIN)/lint-imports

# The documentation as HTML in build/docs: docs/*.md and the API reference generated from the
# docstrings (docs/api/, not kept); any warning is an error
docs: venv
	rm -rf build/docs docs/api
	$(BIN)/sphinx-build -W --keep-going -q -b html docs build/docs
	@echo "docs: $(abspath build/docs/index.html)"

# The table of current figures, docs/figures.md (one planning process at a time; the page
# says how long its run took); the scripts' JSON in results/figures
figures: venv
	PIVOT_BENCH_LOCK=/tmp/pivot-bench.lock $(BIN)/python benchmarks/figures.py \
	    --out results/figures --page docs/figures.md

bench: figures

clean:
	rm -rf $(VENV) $(OUT) build/docs docs/api
