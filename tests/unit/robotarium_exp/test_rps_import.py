"""``import rps...`` resolved name by name: cvxopt's options set by exactly the names whose official modules set
them, unknown names refused, packages empty."""

from __future__ import annotations

import importlib

import cvxopt
import pytest

from robotarium_exp.rps_import import CLASSIC, OFFICIAL_QP_OPTIONS, V2, Generation, use_generation

SETS_OPTIONS = {
    'V2': {'.robotarium', '.utilities.barrier_certificates'},
    'classic': {'.utilities.barrier_certificates', '.utilities.barrier_certificates2'},
}
"""Recorded from the official packages: importing which names (alone, first) changes cvxopt.solvers.options."""


@pytest.mark.usefixtures('clean_rps')
@pytest.mark.parametrize('generation', [V2, CLASSIC], ids=['V2', 'classic'])
def test_cvxopt_options_are_set_by_the_official_modules_that_set_them(generation: Generation) -> None:
    setting = set()
    for suffix in generation.modules:
        use_generation(generation, {})
        cvxopt.solvers.options.clear()
        importlib.import_module('rps' + suffix)
        if cvxopt.solvers.options:
            assert cvxopt.solvers.options == OFFICIAL_QP_OPTIONS
            setting.add(suffix)
    assert setting == SETS_OPTIONS[generation.name]


@pytest.mark.usefixtures('clean_rps')
def test_an_options_module_imported_again_leaves_the_scripts_options() -> None:
    use_generation(V2, {})
    importlib.import_module('rps.robotarium')
    cvxopt.solvers.options['show_progress'] = True
    importlib.import_module('rps.utilities.barrier_certificates')  # imported by rps.robotarium already, as in V2
    assert cvxopt.solvers.options['show_progress'] is True


@pytest.mark.usefixtures('clean_rps')
def test_a_name_the_generation_lacks_is_not_found_and_packages_are_empty() -> None:
    use_generation(V2, {})
    with pytest.raises(ModuleNotFoundError) as missing:
        importlib.import_module('rps.utilities.barrier_certificates2')
    assert missing.value.name == 'rps.utilities.barrier_certificates2'
    with pytest.raises(ModuleNotFoundError):
        importlib.import_module('rps.errors')  # one of our modules, not V2's
    package = importlib.import_module('rps.utilities')
    assert not hasattr(package, 'graph')
    graph = importlib.import_module('rps.utilities.graph')
    assert package.graph is graph and graph is importlib.import_module('robotarium_exp.rps.utilities.graph')
    assert graph.__spec__.name == 'robotarium_exp.rps.utilities.graph'


def test_kept_apart_leaves_the_process_as_it_was() -> None:
    """After a script was given rps inside: no finder of ours, no rps module, cvxopt's options as before."""
    import sys

    from robotarium_exp.rps_import import RpsFinder, kept_apart

    before = dict(cvxopt.solvers.options)
    rps_before = {n for n in sys.modules if n == 'rps' or n.startswith('rps.')}
    with kept_apart():
        use_generation(V2, {})
        importlib.import_module('rps.robotarium')  # V2's imports set the official options
        assert cvxopt.solvers.options['maxiters'] == OFFICIAL_QP_OPTIONS['maxiters']
    assert not any(isinstance(f, RpsFinder) for f in sys.meta_path)
    assert {n for n in sys.modules if n == 'rps' or n.startswith('rps.')} == rps_before
    assert dict(cvxopt.solvers.options) == before
