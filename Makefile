# The two commands a new user runs: `make serve` and `make test`.
# Each creates .venv with the project installed when it is missing, so a
# fresh machine needs nothing but Python 3.11+ and make.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
HOST ?= 127.0.0.1
PORT ?= 8000
WORKERS ?= 1

.PHONY: serve demo test bench bench-service clean

$(BIN)/ephem: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test]'
	touch $(BIN)/ephem

serve: $(BIN)/ephem
	$(BIN)/uvicorn service.app:app --host $(HOST) --port $(PORT) --workers $(WORKERS)

demo: $(BIN)/ephem
	$(BIN)/ephem demo

test: $(BIN)/ephem
	$(BIN)/python -m pytest -q

bench: $(BIN)/ephem
	$(BIN)/python benchmarks/bench_track.py

bench-service: $(BIN)/ephem
	$(BIN)/python benchmarks/bench_service.py

clean:
	rm -rf $(VENV)
