# Two commands on a fresh machine with only Python 3.10+:
#   make run    installs what is needed in .venv, trains PPO on Wind Farm Control's main task, evaluates it on the
#               test seeds beside the paper, the random and the scripted policy, and says where everything is
#   make test   installs the test set-up in .venv and runs the tests and the docs check (the replay page's browser
#               tests need a Chromium: Debian's `chromium` package; HIVEX_SKIP_BROWSER=1 skips them)
# Every install takes .ci/constraints.txt (torch==2.13.0) as a pip constraint: a bare range, or torchvision's exact
# pin (BenchMARL needs torchvision), would pull another torch and GBs of CUDA wheels.

PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin
CONSTRAINTS := .ci/constraints.txt
SCENARIO ?= wind_farm_control/main
# pytest-xdist workers of `make test`, each taking whole test files (module fixtures train once); 2 fills CI's two
# cores and halves its run. `make test TEST_WORKERS=auto` takes one a core; 0 runs in this process.
TEST_WORKERS ?= 2
STEPS ?= 2560000

.PHONY: run test rllib clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

$(VENV)/.installed-run: pyproject.toml $(CONSTRAINTS) | $(BIN)/python
	$(BIN)/pip install --quiet -c $(CONSTRAINTS) torch
	$(BIN)/pip install --quiet -c $(CONSTRAINTS) -e ".[train,plots]"
	touch $@

$(VENV)/.installed-test: pyproject.toml $(CONSTRAINTS) | $(BIN)/python
	$(BIN)/pip install --quiet -c $(CONSTRAINTS) torch
	$(BIN)/pip install --quiet -c $(CONSTRAINTS) -e ".[dev,train,sb3,window,ray,plots,paper,torchrl,benchmarl,browser]"
	touch $@

run: $(VENV)/.installed-run
	$(BIN)/python examples/first_run.py --scenario scenarios/$(SCENARIO).yaml --steps $(STEPS)

test: $(VENV)/.installed-test
	SDL_VIDEODRIVER=dummy $(BIN)/pytest -n $(TEST_WORKERS) --dist loadfile
	$(BIN)/hivex docs --check

# RLlib's install is heavy (ray, ~80 MB wheel plus dependencies): its own target and CI step, in its own venv, since
# ray[rllib] pins an older gymnasium (1.2.2 for ray 2.60) that would replace the test venv's. There the example runs,
# and the Gymnasium, PettingZoo, endings and examples tests run again on RLlib's gymnasium.
RLLIB_VENV ?= .venv-rllib
RLLIB_TESTS := tests/test_gymnasium_conformance.py tests/test_pettingzoo_suite.py tests/test_runtime_endings.py tests/test_supersuit.py \
	tests/test_examples.py tests/test_vector_env.py tests/test_parallel_env.py

rllib:
	$(PYTHON) -m venv $(RLLIB_VENV)
	$(RLLIB_VENV)/bin/pip install --quiet -c $(CONSTRAINTS) torch
	$(RLLIB_VENV)/bin/pip install --quiet -c $(CONSTRAINTS) -e ".[dev,train,rllib]"
	$(RLLIB_VENV)/bin/python examples/rllib_ppo.py --scenario $(SCENARIO) --episode-length 50 --iterations 1 --batch-size 200
	SDL_VIDEODRIVER=dummy $(RLLIB_VENV)/bin/pytest $(RLLIB_TESTS)

clean:
	rm -rf $(VENV)
