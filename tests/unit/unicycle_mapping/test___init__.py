"""The package's curated exports are the defining objects."""

from __future__ import annotations

import importlib

import unicycle_mapping
import unicycle_mapping.errors
import unicycle_mapping.mapping
import unicycle_mapping.unicycle
import unicycle_mapping.wheels


def test_every_export_is_the_object_of_its_defining_module() -> None:
    homes = {'errors', 'mapping', 'unicycle', 'wheels'}
    assert sorted(unicycle_mapping.__all__) == unicycle_mapping.__all__
    for name in unicycle_mapping.__all__:
        exported = getattr(unicycle_mapping, name)
        home = exported.__module__
        assert home.split('.') == ['unicycle_mapping', home.split('.')[-1]] and home.split('.')[-1] in homes
        assert getattr(importlib.import_module(home), name) is exported
