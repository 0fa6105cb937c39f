"""host.app for plugin commands: a plugin found by name, with one clear line when it is not there."""
import pytest

from host.app import plugin_class
from host.errors import UserError


def test_a_plugin_is_found_by_name_and_a_missing_one_names_the_installed_ones():
    synthetic = plugin_class("sources", "synthetic")
    assert synthetic.name == "synthetic" and synthetic.Options(seed=3).seed == 3
    with pytest.raises(UserError, match=r"no source named 'nope'; installed: .*synthetic"):
        plugin_class("sources", "nope")
