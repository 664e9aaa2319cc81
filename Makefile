# Two entry points: `make demo` (plan the regrasp scene, write plan, figure and replay)
# and `make test` (install everything from scratch and run the test suite).
PYTHON ?= python3
VENV   ?= .venv
BIN    := $(VENV)/bin
OUT    ?= out

.PHONY: venv demo test lint bench clean

$(BIN)/pivot-ompl: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e ".[dev,dask]"
	touch $@

venv: $(BIN)/pivot-ompl

demo: venv
	mkdir -p $(OUT)
	$(BIN)/pivot-ompl plan scenes/fig10.yaml --planner regrasp --time 30 --seed 0 \
	    --out $(OUT)/fig10_plan.json --plot $(OUT)/fig10_plan.png
	$(BIN)/pivot-ompl check scenes/fig10.yaml $(OUT)/fig10_plan.json

test: venv
	$(BIN)/python -m pytest -q tests

lint: venv
	$(BIN)/ruff check pivot_ompl tests benchmarks

clean:
	rm -rf $(VENV) $(OUT)
