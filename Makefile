# The two commands of README.md: `make report` (main job) and `make test`.
PYTHON ?= python3
OUT ?= report

.PHONY: setup test report bench
setup:
	bash tools/setup.sh

test: setup
	$(PYTHON) -m pytest -q

report: setup
	csuas range defaults/scenarios/default.toml

bench: setup
	csuas bench
