"""The suite's Hypothesis profiles (tests/conftest.py): bounded and reproducible, or fuzz."""

from __future__ import annotations

from hypothesis import settings


def test_the_default_profile_is_a_bounded_reproducible_run():
    default = settings.get_profile("default")
    assert (default.max_examples, default.derandomize) == (60, True)


def test_the_fuzz_profile_draws_fresh_examples_so_a_seed_changes_them():
    # It once inherited the default's derandomize=True: --hypothesis-seed changed nothing.
    fuzz = settings.get_profile("fuzz")
    assert (fuzz.max_examples, fuzz.derandomize) == (600, False)
