# The two commands of README.md: `make report` (main job) and `make test`.
# Both run tools/setup.sh first, which creates or reuses the virtual environment $(VENV).
VENV ?= $(or $(CSUAS_VENV),.venv)
export CSUAS_VENV := $(VENV)
OUT ?= report

.PHONY: setup test lint report bench
setup:
	bash tools/setup.sh

test: setup
	$(VENV)/bin/python -m pytest -q

lint: setup
	$(VENV)/bin/ruff check .
	$(VENV)/bin/ruff format --check .
	$(VENV)/bin/mypy

report: setup
	$(VENV)/bin/csuas report --quick --out $(OUT)

bench: setup
	$(VENV)/bin/csuas bench
