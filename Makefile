# microslip: commands on a fresh machine.
#   make paper        creates .venv if missing and writes the paper's figures to figures/
#   make figures-ext  creates .venv if missing and writes the extensions' figures (forced
#                     response, v(F, f) under excitation, loss of contact, the friction-
#                     reduction master curve, a mu_eff map, spring-driven stick-slip)
#                     to figures/ext/
#   make test         creates .venv if missing and runs the test suite
#   make docs         creates .venv if missing and builds the documentation (HTML, warnings
#                     as errors, gallery and tutorial executed) into docs/_build/html
#   make bench        the performance table of #10 (job, microslip, peer, ratio, accuracy)
#                     and a scaling plot in benchmarks/out/ (BENCH_ARGS=--quick: ~1 min)
#   make bench-cuda   the time maps on an NVIDIA GPU against the CPU kernel (needs a GPU)
#   make docs-check   checks the built site's links and images, and screenshots it with
#                     headless Chromium (Debian: apt-get install chromium; not run by CI)
PYTHON ?= python3
VENV   ?= .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
FIGDIR ?= figures
EXTDIR ?= $(FIGDIR)/ext

.PHONY: paper figures-ext test lint format bench bench-cuda clean env mutate

env: $(STAMP)

$(STAMP): pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[dev]'
	touch $(STAMP)

paper: $(STAMP)
	$(BIN)/microslip figures --overwrite --out $(FIGDIR)

figures-ext: $(STAMP)
	$(BIN)/microslip figures --extensions --overwrite --out $(EXTDIR)

test: $(STAMP)
	$(BIN)/python -m pytest -q tests

lint: $(STAMP)
	$(BIN)/ruff check src tests benchmarks tools examples docs/conf.py docs/_ext docs/tutorial
	$(BIN)/ruff format --check src tests benchmarks tools examples docs/conf.py docs/_ext docs/tutorial

format: $(STAMP)
	$(BIN)/ruff format src tests benchmarks tools
	$(BIN)/ruff check --fix src tests benchmarks tools

bench: $(STAMP)
	$(BIN)/python benchmarks/bench_table.py $(BENCH_ARGS)

bench-cuda: $(STAMP)
	$(BIN)/python benchmarks/bench_cuda.py $(BENCH_ARGS)

# Mutation testing of model/, integrators/ and analysis/ in a scratch copy, one mutant at a
# time. MUTATE_ARGS: --no-jit (screen fast), --module src/microslip/..., --only FILE:LINE.
mutate: $(STAMP)
	$(BIN)/python tools/mutation/mutate.py $(MUTATE_ARGS)

# Also the compiled-kernel cache (src/microslip/_jit_cache.py): only its jit-* key
# directories, so a MICROSLIP_CACHE_DIR holding other files is never emptied; and numba's
# per-file caches that older versions left next to the sources.
clean:
	rm -rf $(VENV) $(FIGDIR) .pytest_cache
	rm -rf "$${MICROSLIP_CACHE_DIR:-$${XDG_CACHE_HOME:-$$HOME/.cache}/microslip}"/jit-*
	find src -path '*/__pycache__/*' \( -name '*.nbi' -o -name '*.nbc' \) -delete

# Documentation (docs/, examples/): see docs/conf.py. tests/integration/test_docs.py builds
# it the same way and checks the site; docs-check adds screenshots in a real browser.
.PHONY: docs docs-check
DOCSDIR ?= docs/_build/html

docs: $(STAMP)
	$(BIN)/sphinx-build -W --keep-going -b html docs $(DOCSDIR)

docs-check: docs
	$(BIN)/python tools/docs/check_site.py $(DOCSDIR)
	$(BIN)/python tools/docs/screenshots.py $(DOCSDIR) --out docs/_build/screenshots
