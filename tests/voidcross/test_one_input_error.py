"""One ``InputError`` for the whole chain (issue 17): each package re-exports cubot_cad's, so a
bad value raised anywhere is the same exception to a caller and to the CLI (exit 2)."""

import cubot_cad.errors
import structure_fem.errors
import swarm_sim.errors


def test_every_package_raises_the_same_input_error():
    assert swarm_sim.errors.InputError is structure_fem.errors.InputError is cubot_cad.errors.InputError
    assert issubclass(cubot_cad.errors.InputError, ValueError)


def test_a_bad_limits_file_reaches_a_simulation_caller_as_that_error(tmp_path):
    import pytest

    from swarm_sim.runner import resolve_params

    bad = tmp_path / "limits.json"
    bad.write_text("{not json")
    with pytest.raises(swarm_sim.errors.InputError, match="limits.json"):
        resolve_params("case-d", 9, 3, limits=str(bad))
