# Active Voodoo Dolls -- developer commands. Everything runs inside .venv (made on demand), on
# CPython 3.11 and NumPy 1.26 with bpy 5.0.1 as Blender 5.0 has them; the tests also run in real
# Blender 5.2 LTS and 5.1 (bpy on CPython 3.13 and NumPy 2) in a Debian 13 root
# (scripts/blender_next.sh, made once and cached under /var/cache/voodoo-next; needs root).
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed-$(shell cat requirements.txt requirements-test.txt requirements-dev.txt | cksum | cut -d' ' -f1)
# bpy releases tested besides 5.0.1: 5.2 LTS and the last 5.1.
BLENDER_NEXT := 5.2.3 5.1.2

.PHONY: setup mesa test test-blender-next fuzz demo bench lint extension clean

setup: $(STAMP)

$(STAMP): requirements.txt requirements-test.txt requirements-dev.txt
	$(PYTHON) -m venv $(VENV) || { scripts/ensure_debs.sh python3-venv && $(PYTHON) -m venv $(VENV); }
	$(BIN)/python -m pip install -q --upgrade pip
	$(BIN)/python -m pip install -q -r requirements-dev.txt
	rm -f $(VENV)/.installed-*
	touch $@

mesa:
	@scripts/ensure_debs.sh libegl1 libegl-mesa0 libgl1-mesa-dri libgbm1

## Run the whole test suite: everything (engine, packaging -- the extension zips and pip install --,
## the real Blender headless) on Blender 5.0, then the same in Blender 5.2 and 5.1
## (test-blender-next). About 7 + 9 minutes on 2 cores once the packages are installed; a fresh
## clone with nothing installed took 17 minutes in all (.ci/run).
test: setup mesa
	$(BIN)/python -m pytest
	@$(MAKE) --no-print-directory test-blender-next

## Everything again in real Blender 5.2 LTS (CPython 3.13, NumPy 2: requirements-next.txt): the
## engine, the packaging with 5.2's own extension code, the Blender suite and the install of the
## Linux zip; then the Blender suite and the install in the last 5.1. The first run makes the
## Debian 13 root (about a minute) and one virtualenv per bpy there.
test-blender-next:
	scripts/blender_next.sh $(word 1,$(BLENDER_NEXT)) tests
	@for v in $(wordlist 2,9,$(BLENDER_NEXT)); do scripts/blender_next.sh $$v tests/blender || exit 1; done

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
