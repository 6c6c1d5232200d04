"""Figures' own arithmetic: the gait frequency read off contact records, the thesis notes in titles."""

from mjx_badger.experiments.registry import EXPERIMENTS
from mjx_badger.outputs import plots, tables


def test_every_experiment_declares_figures_and_a_table_that_exist():
    for experiment in EXPERIMENTS.values():
        assert set(experiment.figures) <= set(plots.FIGURES), experiment.name
        assert experiment.table in tables.TABLES and experiment.x_axis in ("steps", "minutes"), experiment.name
        assert ("versus" in experiment.figures) == (experiment.baseline in EXPERIMENTS), experiment.name


