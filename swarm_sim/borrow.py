"""Borrowed array views for compiled calls: the same data, shape and strides, no reference count.

numba passes an array to a compiled function it calls (or inlines) together with its
memory-info pointer, and the callee increments and decrements that count: two atomic
operations per array per call. The compiled engine calls the walk (16 arrays) once a step
and each recruit's drive helpers (several arrays) once per recruit and step, so those
counts were a measurable part of a step (~230 ns of the walk's call alone, measured on the
large void). :func:`borrowed` gives a view whose memory-info pointer is null: numba's
``NRT_incref``/``NRT_decref`` return at once for a null pointer, so passing it costs a test,
not an atomic operation.

A borrowed view does not keep its array alive. Take it inside a compiled function from an
array that the function itself holds (an argument, or an array it allocated) and pass it only
to calls that return before that array goes: never return it or store it.
"""

from __future__ import annotations

from .grid import HAVE_NUMBA

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


__all__ = ["borrowed"] if HAVE_NUMBA else []
