# The two commands of the README do the whole set-up themselves.
PYTHON ?= python3
VENV ?= .venv
PY := $(VENV)/bin/python
PROFILE ?= quick
PROTOCOL ?= thesis-code
# Test files run in this many processes, a file's tests in one (they share its compiled functions).
TEST_WORKERS ?= 2

# The documentation site, strict: a page left out of nav, a broken link or anchor, or a missing figure fails it.
# NO_MKDOCS_2_WARNING silences mkdocs-material's notice about its end of life, which is not a warning of the build.
MKDOCS := NO_MKDOCS_2_WARNING=1 $(VENV)/bin/mkdocs build --strict --site-dir build/site

.PHONY: install test test-slow docs reproduce-figures figures reference-figures grid-figure benchmark bench-peers clean

# uv installs the pinned set in seconds where pip takes half a minute; pip does it where uv cannot reach an index.
$(VENV)/.installed: pyproject.toml requirements.lock
	$(PYTHON) -m venv $(VENV)
	$(VENV)/bin/pip install --quiet uv==0.13.9 \
	  && $(VENV)/bin/uv pip install --quiet --python $(PY) -r requirements.lock \
	  || $(VENV)/bin/pip install --quiet -r requirements.lock
	$(VENV)/bin/pip install --quiet --no-deps -e .
	touch $@

install: $(VENV)/.installed

test: install
	$(VENV)/bin/ruff check mjx_badger tests benchmarks tools docs
	$(VENV)/bin/lint-imports --no-cache
	$(MKDOCS) --quiet
	$(PY) -m pytest -q -n $(TEST_WORKERS) --dist loadfile

docs: install
	$(MKDOCS)

test-slow: install
	$(PY) -m pytest -q -m slow -n $(TEST_WORKERS) --dist loadfile

# A user's run: results, figures and scoreboard all under results/ (git-ignored; docs/robustness.md).
reproduce-figures: install
	$(PY) -m mjx_badger reproduce --profile $(PROFILE) --protocol $(PROTOCOL)

figures: install
	$(PY) -m mjx_badger figures --profile $(PROFILE) --protocol $(PROTOCOL)

# Maintainers: the committed figures and scoreboard redrawn from the committed results (figures/data), by name.
reference-figures: install
	$(PY) -m mjx_badger figures --results-dir figures/data --figures-dir figures --profile $(PROFILE) --protocol $(PROTOCOL)
	$(PY) -m mjx_badger claims --results-dir figures/data --profile $(PROFILE) --markdown figures/claims_$(PROFILE).md

# Fig 4.2's learning rate x batch size grid at quick (24 sweep members, about 6 h on a 2-core CPU; resumable).
grid-figure: install
	$(PY) -m tools.lr_batch_grid --run --results-dir results/grid --figures-dir results/grid/figures

# Each benchmark is a module of the benchmarks package, run from the repository root (docs/benchmarks.md).
benchmark: install
	$(PY) -m benchmarks.bench_spine
	$(PY) -m benchmarks.bench_contacts
	$(PY) -m benchmarks.bench_algorithms
	$(PY) -m benchmarks.bench_realtime

# Peers (sbx CrossQ, with Stable-Baselines3 and PyTorch) go into the venv only here, never for `make test`.
bench-peers: install
	$(VENV)/bin/pip install --quiet -r requirements-peers.lock
	$(PY) -m benchmarks.bench_peers

clean:
	rm -rf $(VENV) results .pytest_cache
