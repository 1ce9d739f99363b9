"""The files here are shrunk failures of the fuzzer (validation/stress/fuzz_run.py): mutated case files,
each under a comment header naming the problem it showed (``fuzz regression``), the verb it is run with,
its source case and mutations, what was seen, its ``status`` and the ``defect``. tests/validation/test_fuzz.py
replays each through the command line: ``fixed`` must keep the contract (exit 0, 1 or 2 in time, one-line
messages, no traceback, finite numbers on exit 0); ``open`` is an expected failure until the defect is
fixed. They are not case files to validate: the case-file plugin (validation/pytest_plugin.py) must not
collect them."""

collect_ignore_glob = ["*.toml"]
