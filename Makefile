# The two commands of README.md: `make report` (main job) and `make test`.
PYTHON ?= python3
OUT ?= report

.PHONY: setup test report bench
setup:
	bash tools/setup.sh

test: setup
	$(PYTHON) -m pytest -q

report: setup
	csuas report --quick --out $(OUT)

bench: setup
	csuas bench
