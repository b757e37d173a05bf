"""Each run option is declared once (``runner.options``): its field of ``RunOptions``
carries its flag, from which ``skfem-cable run`` is built and read back, and the opt-in
options are refused by the scenes that do not name them."""

import argparse
from dataclasses import fields

import pytest

from skfem_cable.cli import command as cli
from skfem_cable.runner.options import DEFAULTS, FLAGS, OPT_IN, RunOptions, flag
from skfem_cable.scenes import catalog


def _run_parser():
    sub = next(a for a in cli.build_parser()._actions
               if isinstance(a, argparse._SubParsersAction))
    return sub.choices["run"]


def test_every_option_has_one_flag_and_reads_back():
    """Every field of ``RunOptions`` is one flag of ``run`` (and nothing else is), and the
    parsed arguments give the options back: given values, negated switches, defaults."""
    dests = [a.dest for a in _run_parser()._actions if a.dest not in ("help", "scene")]
    assert sorted(dests) == sorted(f.name for f in fields(RunOptions))
    args = cli.build_parser().parse_args(
        ["run", "esail", "--t-end", "2min", "--no-progress", "--alpha", "-3", "--resume"])
    options = RunOptions.from_args(args)
    assert (options.t_end, options.progress, options.alpha, options.resume) == \
        (120.0, False, -3.0, True)
    untouched = {n: getattr(options, n) for n in DEFAULTS
                 if n not in ("t_end", "progress", "alpha", "resume")}
    assert untouched == {n: DEFAULTS[n] for n in untouched}
    assert flag("plots") == "--no-plots" and flag("t_end") == "--t-end"


@pytest.mark.parametrize("scene", ["pendulum", "tss", "cantilever", "hanging-chain"])
def test_opt_in_options_are_refused_by_the_scenes_that_do_not_name_them(scene):
    """``--alpha`` is an opt-in option of the E-sail scenes, refused elsewhere by the
    catalog (no scene writes the refusal itself)."""
    assert set(OPT_IN) == {"alpha", "model", "element", "epoch"}
    assert all(FLAGS[n].opt_in for n in OPT_IN)
    assert "alpha" in catalog.SCENES["esail"].takes
    with pytest.raises(ValueError, match=f"scene '{scene}' does not take --alpha"):
        catalog.run_scene(scene, RunOptions(alpha=10.0))
