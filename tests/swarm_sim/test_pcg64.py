"""The compiled engine's in-kernel stream (swarm_sim.engine.pcg64) is numpy's Generator.random(), bit for bit."""

import numpy as np
import pytest

from swarm_sim.engine import pcg64
from swarm_sim.engine.grid import HAVE_NUMBA


@pytest.mark.parametrize("seed", [0, 1, 1000, 2**32 + 7, 2**63 + 12345])
def test_the_python_reference_is_numpys_stream(seed):
    rng = np.random.default_rng(seed)
    rng.random(3)
    w = [int(v) for v in pcg64.words(rng)]
    assert [pcg64.next_double_py(w) for _ in range(50)] == list(rng.random(50))


@pytest.mark.skipif(not HAVE_NUMBA, reason="numba not installed")
@pytest.mark.parametrize("seed", [0, 5, 1001, 2**40 + 3, 2**64 - 1])
def test_the_kernel_draws_are_rng_random_in_c_order(seed):
    """As the kernel uses them: each step's 4 x k block read through the jump table from the
    step's start, then the stream jumped past it; 64 steps are numpy's rng.random((64, 4, k))."""
    rng = np.random.default_rng(seed)
    rng.random(11)
    w = pcg64.words(rng)
    k = 9
    table = np.empty((4 * k, 4), np.uint64)
    pcg64.jump_table(w, 4 * k, table)
    got = np.empty((64, 4, k))
    for step in range(64):
        got[step] = np.array([pcg64.draw_at(w, table, j) for j in range(4 * k)]).reshape(4, k)
        pcg64.jump(w, table, 4 * k)
    assert np.array_equal(got, rng.random((64, 4, k)))
    # the words moved exactly as the generator did: the next draws agree too
    other = np.random.default_rng(seed)
    pcg64.store(other, w)
    assert np.array_equal(other.random(20), rng.random(20))


@pytest.mark.skipif(not HAVE_NUMBA, reason="numba not installed")
def test_store_keeps_the_32_bit_buffer_and_words_round_trip():
    rng = np.random.default_rng(9)
    rng.integers(0, 2**32, dtype=np.uint32)  # leaves a buffered 32-bit half
    before = rng.bit_generator.state
    assert before["has_uint32"] == 1
    w = pcg64.words(rng)
    pcg64.store(rng, w)
    assert rng.bit_generator.state == before
    assert pcg64.supported(rng) and not pcg64.supported(np.random.Generator(np.random.MT19937(1)))


@pytest.mark.skipif(not HAVE_NUMBA, reason="numba not installed")
def test_a_generator_that_is_not_pcg64_gets_reference_steps_and_the_same_run():
    from swarm_sim import compiled
    from swarm_sim.engine.world import World
    from swarm_sim.runner import init_state, resolve_params

    p = resolve_params("case-d", 3, 1, "thesis", 5.0)
    world = World.from_params(p)
    mt = np.random.Generator(np.random.MT19937(3))
    state = init_state(p, mt)
    same, steps, _ = compiled.fast_forward(state, p, world, mt)
    assert steps == 0 and same is state
    pc = np.random.default_rng(3)
    _, steps, _ = compiled.fast_forward(init_state(p, pc), p, world, pc)
    assert steps > 0


@pytest.mark.skipif(not HAVE_NUMBA, reason="numba not installed")
@pytest.mark.parametrize("seed", [0, 7, 1002, 2**64 - 1])
def test_a_draw_read_out_of_order_is_the_one_numpy_draws_there_and_the_jump_lands_where_numpy_does(seed):
    rng = np.random.default_rng(seed)
    rng.random(5)
    w = pcg64.words(rng)
    m = 4 * 13
    table = np.empty((m, 4), np.uint64)
    pcg64.jump_table(w, m, table)
    want = rng.random(m)  # the step's 4 x 13 numbers, in C order
    order = np.random.default_rng(1).permutation(m)  # read in any order, each from the step's start
    assert [pcg64.draw_at(w, table, int(j)) for j in order] == list(want[order])
    for steps in (1, 17, m):  # the jump moves the words by exactly that many draws
        moved = w.copy()
        pcg64.jump(moved, table, steps)
        fresh = np.random.default_rng(seed)
        fresh.random(5 + steps)
        assert np.array_equal(moved, pcg64.words(fresh))



@pytest.mark.parametrize("seed", [0, 9, 2**63 + 1])
def test_words_and_store_read_and_write_the_generators_own_memory_as_its_state_dict_says(seed, monkeypatch):
    src = np.random.default_rng(seed)
    src.random(7)
    w = pcg64.words(src)
    assert w.tolist() == pcg64._words_by_dict(src).tolist()
    dst = np.random.default_rng(seed + 1)
    dst.random(3)
    pcg64.store(dst, w)
    s, d = src.bit_generator.state, dst.bit_generator.state
    assert s["state"] == d["state"] and d["has_uint32"] == 0
    assert np.array_equal(dst.random(5), src.random(5))
    # a layout not recognised: the state dict is read and written instead, with the same result
    monkeypatch.setattr(pcg64, "_ORDER", [None])
    again = np.random.default_rng(seed + 2)
    pcg64.store(again, pcg64.words(src))
    assert np.array_equal(again.random(5), src.random(5))
