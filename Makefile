# Active Voodoo Dolls -- developer commands. Everything runs inside .venv (made on demand).
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed-$(shell cat requirements.txt requirements-test.txt requirements-dev.txt | cksum | cut -d' ' -f1)

.PHONY: setup mesa test demo bench lint extension clean

setup: $(STAMP)

$(STAMP): requirements.txt requirements-test.txt requirements-dev.txt
	$(PYTHON) -m venv $(VENV) || { scripts/ensure_debs.sh python3-venv && $(PYTHON) -m venv $(VENV); }
	$(BIN)/python -m pip install -q --upgrade pip
	$(BIN)/python -m pip install -q -r requirements-dev.txt
	rm -f $(VENV)/.installed-*
	touch $@

mesa:
	@scripts/ensure_debs.sh libegl1 libegl-mesa0 libgl1-mesa-dri libgbm1

## Run the whole test suite (engine + packaging + real Blender, headless).
test: setup mesa
	$(BIN)/python -m pytest

## Build a blob from the sample take, track it, apply it to the sample characters.
demo: setup mesa
	$(BIN)/python scripts/demo.py

## Tracking speed and accuracy (single-threaded), see BENCHMARKS.md.
bench: setup
	$(BIN)/python -m voodoo_addon bench

## Download the manifest's wheels and build one validated extension zip per platform into dist/,
## each holding the wheels for Blender 5.0 (CPython 3.11) and 5.1 and later (CPython 3.13).
extension: setup
	$(BIN)/python scripts/build_extension.py

lint: setup
	$(BIN)/ruff check .

clean:
	rm -rf out dist wheels .pytest_cache
