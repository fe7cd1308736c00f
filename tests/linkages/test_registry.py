"""The linkage registry: one entry per mechanism, found by kind and by type name."""

import dataclasses

import numpy as np
import pytest

import sso
from sso._cases.mechanism import ANALYSIS_KINDS
from sso._linkages.registry import linkage_of, linkage_of_kind, linkages, register


def test_every_mechanism_is_registered_once_in_module_order():
    assert list(linkages()) == ["fourbar", "slider_crank", "quick_return"]
    assert ANALYSIS_KINDS == ("fourbar", "slider_crank", "quick_return")
    assert [entry.mechanism for entry in linkages().values()] == [
        sso.FourBar, sso.SliderCrank, sso.QuickReturn]


def test_an_entry_is_found_by_kind_by_instance_and_by_type_name():
    fourbar = sso.FourBar(ground=12, crank=2, coupler=15, rocker=9)
    assert linkage_of(fourbar) is linkage_of_kind("fourbar") is linkage_of("FourBar")
    with pytest.raises(KeyError, match="Hexapod"):
        linkage_of("Hexapod")


def test_each_entry_names_real_fields_and_columns():
    # The link names are the constructor's fields, and every listed column is one
    # the mechanism's table has (so no entry can name a column that never exists).
    samples = {"fourbar": {"ground": 12, "crank": 2, "coupler": 15, "rocker": 9},
               "slider_crank": {"crank": 0.05, "rod": 0.2},
               "quick_return": {"crank": 2, "coupler": 7, "rocker": 9, "slider_link": 4,
                                "ground": 6}}
    for kind, entry in linkages().items():
        fields = [field.name for field in dataclasses.fields(entry.mechanism)]
        assert list(entry.links) + [entry.extra] == fields[:len(entry.links) + 1]
        table = entry.mechanism(**samples[kind]).analyse(
            np.arange(0.0, 360.0, 30.0), crank_speed=1.0, on_unassembled="mark")
        plotted = {column for _, _, panels in entry.series_plots for _, curves in panels
                   for column, *_ in curves for column in column.split("-")}
        for column in {*entry.report_columns, *entry.extreme_columns, *plotted} - {
                "coupler_point_x", "coupler_point_y"}:
            assert column in table.columns, (kind, column)


def test_a_second_class_under_a_known_kind_is_refused():
    entry = linkage_of_kind("fourbar")
    with pytest.raises(ValueError, match="registered twice"):
        register(dataclasses.replace(entry, mechanism=sso.SliderCrank))
