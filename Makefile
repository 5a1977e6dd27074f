# Active Voodoo Dolls -- developer commands. Everything runs inside .venv (made on demand), on
# NumPy 1.26 with bpy 5.0 as Blender 5.0 has them; the engine is also tested in .venv-np2, on
# NumPy 2 as Blender 5.1 and later have it.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed-$(shell cat requirements.txt requirements-test.txt requirements-dev.txt | cksum | cut -d' ' -f1)
VENV2  := .venv-np2
BIN2   := $(VENV2)/bin
STAMP2 := $(VENV2)/.installed-$(shell cat requirements.txt requirements-test.txt requirements-numpy2.txt | cksum | cut -d' ' -f1)

.PHONY: setup setup-numpy2 mesa test test-numpy2 fuzz demo bench lint extension clean

setup: $(STAMP)

$(STAMP): requirements.txt requirements-test.txt requirements-dev.txt
	$(PYTHON) -m venv $(VENV) || { scripts/ensure_debs.sh python3-venv && $(PYTHON) -m venv $(VENV); }
	$(BIN)/python -m pip install -q --upgrade pip
	$(BIN)/python -m pip install -q -r requirements-dev.txt
	rm -f $(VENV)/.installed-*
	touch $@

setup-numpy2: $(STAMP2)

$(STAMP2): requirements.txt requirements-test.txt requirements-numpy2.txt
	$(PYTHON) -m venv $(VENV2) || { scripts/ensure_debs.sh python3-venv && $(PYTHON) -m venv $(VENV2); }
	$(BIN2)/python -m pip install -q --upgrade pip
	$(BIN2)/python -m pip install -q -r requirements-numpy2.txt
	rm -f $(VENV2)/.installed-*
	touch $@

mesa:
	@scripts/ensure_debs.sh libegl1 libegl-mesa0 libgl1-mesa-dri libgbm1

## Run the whole test suite: everything (engine, packaging -- the extension zips and pip install --,
## the real Blender headless) on NumPy 1.26, then the whole engine suite, slow tests included, on
## NumPy 2 (test-numpy2). About 4 + 3 minutes on 2 cores once the packages are installed.
test: setup mesa
	$(BIN)/python -m pytest
	@$(MAKE) --no-print-directory test-numpy2

## The engine tests on NumPy 2 (requirements-numpy2.txt): Blender 5.1 and later ship NumPy 2.x.
test-numpy2: setup-numpy2
	$(BIN2)/python -m pytest tests/engine

## The fuzz test for four minutes per part (the suite runs it for 15 s per part); pick other
## inputs with VOODOO_FUZZ_SEED=n.
fuzz: setup
	VOODOO_FUZZ_SECONDS=240 $(BIN)/python -m pytest tests/engine/test_fuzz.py

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
	rm -rf out dist wheels build *.egg-info .pytest_cache
