"""Finite but extreme values are refused by the Python module as by the command line
(the same checks: config/value_ranges.hpp), naming the key or the state file's line."""
import pytest

import ballagg


@pytest.mark.parametrize("sections, key", [
    ({"system": {"radius": 1e102, "dimension": 3}}, "system.radius"),
    ({"system": {"mass": 1e307}}, "system.mass"),
    ({"initial": {"speed": 1e300}}, "initial.speed"),
    ({"engine": {"skin": 1e-300}}, "engine.skin"),
    ({"system": {"volume_fraction": 1e-12}}, "system.volume_fraction"),
])
def test_extreme_values_raise_input_error_naming_the_key(sections, key):
    with pytest.raises(ballagg.InputError, match=key):
        ballagg.Simulation(sections)


def test_a_state_file_row_with_a_huge_speed_raises_naming_the_line(tmp_path):
    state = tmp_path / "state.csv"
    state.write_text("x,y,vx,vy,radius,mass\n1,1,0,0,0.2,1\n5,5,1e308,0,0.2,1\n")
    config = {"system": {"box_length": 10.0}, "initial": {"positions": "file", "file": str(state)}}
    with pytest.raises(ballagg.InputError, match=r"state.csv:3: columns vx,vy: the speed 1e\+308 is above 1e\+20"):
        ballagg.Simulation(config)
