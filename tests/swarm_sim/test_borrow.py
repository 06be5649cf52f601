"""A borrowed view (swarm_sim.engine.borrow) is the array's own data, shape and strides, with no
memory-info pointer, so the compiled calls it is passed to count no references."""

import numpy as np
import pytest

from swarm_sim.engine.grid import HAVE_NUMBA

pytestmark = pytest.mark.skipif(not HAVE_NUMBA, reason="numba not installed")

if HAVE_NUMBA:
    import numba
    from numba.core import types
    from numba.extending import intrinsic
    from numba.np.arrayobj import make_array

    from swarm_sim.engine.borrow import borrowed

    @intrinsic
    def _meminfo_is_null(typingctx, arr):
        """Test probe: the array's memory-info pointer is null."""
        def codegen(context, builder, sig, args):
            a = make_array(sig.args[0])(context, builder, value=args[0])
            return builder.icmp_unsigned("==", a.meminfo, a.meminfo.type(None))
        return types.boolean(arr), codegen

    @numba.njit
    def _add_through(a, v):
        for i in range(a.shape[0]):
            a[i] += v
        return a.sum()

    @numba.njit
    def _probe(a):
        b = borrowed(a)
        row = borrowed(a)[1]  # a view of a borrowed view is borrowed too
        total = _add_through(row, 1.0)
        return _meminfo_is_null(a), _meminfo_is_null(b), _meminfo_is_null(row), b.shape[0], b.shape[1], \
            b.strides[0], b.strides[1], b[2, 1], total


def test_a_borrowed_view_is_the_arrays_data_and_layout_without_a_reference_count():
    base = np.arange(24.0).reshape(4, 6)
    a = base[:, ::2]  # not contiguous: the strides carry over
    own_null, b_null, row_null, s0, s1, st0, st1, v21, total = _probe(a)
    assert not own_null and b_null and row_null
    assert (s0, s1, st0, st1) == (*a.shape, *a.strides)
    assert v21 == a[2, 1]
    # the helper wrote through the borrowed row into the caller's array
    assert np.array_equal(base[1], [7.0, 7.0, 9.0, 9.0, 11.0, 11.0])
    assert total == 7.0 + 9.0 + 11.0


def test_borrowed_refuses_what_is_not_an_array():
    @numba.njit
    def f(v):
        return borrowed(v)

    with pytest.raises(numba.core.errors.TypingError):
        f(3.0)
