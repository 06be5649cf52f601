"""Borrowed array views for compiled calls: the same data, shape and strides, no reference count.

numba passes an array to a compiled function it calls (or inlines) together with its
memory-info pointer, and the callee increments and decrements that count: two atomic
operations per array per call. The compiled engine calls the walk (16 arrays) once a step
and each recruit's drive helpers (several arrays) once per recruit and step, so those
counts were a measurable part of a step (~230 ns of the walk's call alone, measured on the
large void). :func:`borrowed` gives a view whose memory-info pointer is null: numba's
``NRT_incref``/``NRT_decref`` return at once for a null pointer, so passing it costs a test,
not an atomic operation.

:func:`float64_at`, :func:`int64_at` and :func:`bool_at` make the same kind of view from a data
address (:func:`address`): the compiled engine hands its kernel the recruits' cost fields as a
table of addresses, so a field is read where it lies (and seen as it settles further) instead of
being copied into one stacked array per call.

A borrowed view does not keep its array alive. Take it inside a compiled function from an
array that the function itself holds (an argument, or an array it allocated) and pass it only
to calls that return before that array goes: never return it or store it.
"""

from __future__ import annotations

import numpy as np

from swarm_sim.engine.grid import HAVE_NUMBA

if HAVE_NUMBA:
    from numba.core import types
    from numba.extending import intrinsic
    from numba.np.arrayobj import make_array, populate_array

    @intrinsic
    def borrowed(typingctx, arr):
        """A view of ``arr`` (any numba array) without a memory-info pointer (module docstring)."""
        if not isinstance(arr, types.Array):
            return None

        def codegen(context, builder, sig, args):
            src = make_array(sig.args[0])(context, builder, value=args[0])
            out = make_array(sig.return_type)(context, builder)
            populate_array(out, data=src.data, shape=src.shape, strides=src.strides, itemsize=src.itemsize,
                           meminfo=None)
            return out._getvalue()

        return arr(arr), codegen

    def _pointer_at(nbtype):
        @intrinsic
        def at(typingctx, addr):
            if not isinstance(addr, types.Integer):
                return None

            def codegen(context, builder, sig, args):
                return builder.inttoptr(args[0], context.get_value_type(sig.return_type))

            return types.CPointer(nbtype)(addr), codegen

        return at

    #: a data pointer from an address (``arr.ctypes.data``), for ``numba.carray(float64_at(a), n)``:
    #: a borrowed view of an array the compiled code is not passed (the caller keeps it alive)
    float64_at = _pointer_at(types.float64)
    int64_at = _pointer_at(types.int64)
    bool_at = _pointer_at(types.boolean)


def address(a: np.ndarray, dtype) -> int:
    """The data address of ``a`` for :func:`float64_at` / :func:`int64_at` / :func:`bool_at`, after
    checking that it is a C-contiguous array of ``dtype`` (what the view will read it as)."""
    if a.dtype != dtype or not a.flags.c_contiguous:
        raise TypeError(f"a borrowed view needs a C-contiguous {np.dtype(dtype)} array, got {a.dtype}")
    return a.__array_interface__["data"][0]


__all__ = ["address"] + (["bool_at", "borrowed", "float64_at", "int64_at"] if HAVE_NUMBA else [])
