"""The specs' base: a rule on options that go together raises the field it names."""

import pytest
from pydantic import model_validator

from marinecdpr.commands.base import Spec, SpecError


class _Job(Spec):
    surface: bool = False
    hull_area: float | None = None

    @model_validator(mode="after")
    def _together(self):
        if self.surface and self.hull_area is not None:
            raise SpecError("hull_area", self.hull_area, "cannot go with --surface")
        return self


def test_a_rule_on_options_that_go_together_names_the_field_it_chose():
    with pytest.raises(SpecError) as err:
        _Job(surface=True, hull_area=5000.0)
    assert (err.value.field, err.value.value, err.value.flag) == ("hull_area", "5000", "--hull-area")
    assert str(err.value) == "hull_area 5000: cannot go with --surface"
    assert _Job(hull_area=5000.0).hull_area == 5000.0  # alone, each is fine


def test_an_unknown_option_is_named_with_the_spec_s_class():
    with pytest.raises(SpecError) as err:
        _Job(hull_aera=5.0)
    assert (err.value.field, err.value.detail) == ("hull_aera", "no such option of _Job")
