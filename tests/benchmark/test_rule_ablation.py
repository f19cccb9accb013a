"""``benchmarks/rule_ablation.py``: every rule it switches off names settings the recognizer
knows and that change something, and its usage errors are one line."""

from __future__ import annotations

import subprocess
import sys

import pytest

from benchmark_scripts import BENCH, load_benchmark
from framefree.online import RecognizerConfig
from framefree.online.learned import split_settings


@pytest.fixture(scope="module")
def rule_ablation():
    return load_benchmark("rule_ablation")


def test_every_rule_switches_something_off(rule_ablation):
    """Each rule's settings are known to the recognizer (a misspelt name raises) and differ from
    the shipped recognizer: a changed setting, or a learned value given instead of derived."""
    assert rule_ablation.RULES["none"][1] == {}
    for name, (_, settings) in rule_ablation.RULES.items():
        config, given = split_settings(dict(settings))
        if name == "none":
            assert config == RecognizerConfig() and not given
        else:
            assert config != RecognizerConfig() or given, name


@pytest.mark.parametrize(("args", "named"), [(["--rules", "travel,no_such_rule"], "no_such_rule"),
                                            (["--rules", ","], "--rules"),
                                            (["--jobs", "0"], "--jobs")])
def test_usage_errors_are_one_line_and_exit_2(args, named):
    proc = subprocess.run([sys.executable, str(BENCH / "rule_ablation.py"), *args],
                          capture_output=True, text=True)
    assert proc.returncode == 2
    assert proc.stderr.strip().count("\n") == 0 and named in proc.stderr
