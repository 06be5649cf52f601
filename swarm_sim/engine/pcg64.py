"""numpy's PCG64 stream inside compiled code: ``Generator.random()`` drawn in a kernel, bit for bit.

The compiled engine (:mod:`swarm_sim.compiled`) used to pre-draw a whole batch of uniform
numbers with ``rng.random((S, 4, k))`` before each kernel call, then rewind the stream when
the kernel stopped early: up to 4 million doubles per call drawn, a third of them thrown
away (measured: 10.1 M drawn for 6.7 M used per large-void run, about 70 ms of its 700 ms).
Here the kernel draws each number when it needs it from the generator's own state:

* :func:`words` reads a ``np.random.PCG64``'s 128-bit state and increment as four uint64
  words ``(state_hi, state_lo, inc_hi, inc_lo)``; :func:`store` writes them back
  (``has_uint32``/``uinteger``, the 32-bit buffer ``random()`` never touches, are kept);
* a draw is numpy's ``pcg_setseq_128_xsl_rr_64`` step (``state = state * M + inc`` mod 2^128,
  then ``rotr64(hi ^ lo, hi >> 58)``) and its double, ``(u64 >> 11) * 2^-53``
  (:func:`next_double_py` in pure Python, the reference of the tests).

A step of the walk draws ``4 x k`` numbers but, with the Levy walk, reads few of them (a
hazard's turn, the end of a run), so none is drawn in sequence: :func:`jump_table` precomputes the affine maps
``state -> A_m * state + C_m`` (mod 2^128) of ``m = 1 .. 4k`` advances once per kernel call, so
:func:`draw_at` computes the ``j``-th draw of a step directly from the step's start state (one
128-bit multiply-add, whatever ``j``) and :func:`jump` moves the stream past the whole step:
the numbers read are the same and the stream ends where numpy's would, at a fraction of the
cost (PCG's jump-ahead: O'Neill 2014, section 4.3.1; numpy's ``PCG64.advance`` does the same).

``tests/swarm_sim/test_pcg64.py`` compares it with numpy on many seeds and states.
"""

from __future__ import annotations

import ctypes

import numpy as np

from swarm_sim.engine.grid import HAVE_NUMBA, numba

#: PCG's default 128-bit multiplier (numpy ``pcg64.h``: PCG_DEFAULT_MULTIPLIER_HIGH / _LOW)
MULT_HI = 2549297995355413924
MULT_LO = 4865540595714422341
_M64 = (1 << 64) - 1


def supported(rng: np.random.Generator) -> bool:
    """The generator's stream is one :func:`draw_at` reproduces (a PCG64 bit generator)."""
    return type(rng.bit_generator) is np.random.PCG64


def _words_by_dict(rng: np.random.Generator) -> np.ndarray:
    s = rng.bit_generator.state["state"]
    st, inc = int(s["state"]), int(s["inc"])
    return np.array([st >> 64, st & _M64, inc >> 64, inc & _M64], dtype=np.uint64)


def _store_by_dict(rng: np.random.Generator, w: np.ndarray) -> None:
    bg = rng.bit_generator
    full = bg.state
    full["state"] = {"state": (int(w[0]) << 64) | int(w[1]), "inc": (int(w[2]) << 64) | int(w[3])}
    bg.state = full


#: where :func:`words`' four words lie in numpy's ``pcg64_random_t`` (state, inc: two 128-bit
#: numbers), found once by comparing with the ``state`` dict; None: read and write the dict
_ORDER: list = []


def _memory(rng: np.random.Generator) -> np.ndarray | None:
    """The generator's ``pcg64_random_t`` as four uint64 words in its own memory (a view: the
    ``ctypes`` interface numpy gives every bit generator), in :func:`words`' order, or None when
    the layout is not one known here (then the ``state`` dict is used: same numbers, slower)."""
    bg = rng.bit_generator
    ptr = ctypes.c_void_p.from_address(bg.ctypes.state_address).value  # pcg64_state.pcg_state
    raw = np.frombuffer((ctypes.c_uint64 * 4).from_address(ptr), dtype=np.uint64)
    if not _ORDER:
        ref = _words_by_dict(rng).tolist()
        for order in ((1, 0, 3, 2), (0, 1, 2, 3)):  # native little-endian 128-bit ints, or numpy's
            if [int(raw[i]) for i in order] == ref:  # emulated {high, low} struct
                _ORDER.append(np.array(order))
                break
        else:
            _ORDER.append(None)
    return None if _ORDER[0] is None else raw


def words(rng: np.random.Generator) -> np.ndarray:
    """The generator's PCG64 state as ``uint64[4]`` = (state hi, state lo, inc hi, inc lo): read
    from its memory (~2 us; the ``state`` dict took ~8 us)."""
    raw = _memory(rng)
    return _words_by_dict(rng) if raw is None else raw[_ORDER[0]]


def store(rng: np.random.Generator, w: np.ndarray) -> None:
    """Set the generator's PCG64 state from :func:`words`' layout (its 32-bit buffer unchanged),
    in its memory."""
    raw = _memory(rng)
    if raw is None:
        _store_by_dict(rng, w)
    else:
        raw[_ORDER[0]] = w


def next_double_py(w: list[int]) -> float:
    """One draw in pure Python on a list of four ints (advanced in place): ``Generator.random()``
    (the reference the compiled :func:`draw_at` / :func:`jump` are tested against)."""
    st = (w[0] << 64) | w[1]
    inc = (w[2] << 64) | w[3]
    st = (st * ((MULT_HI << 64) | MULT_LO) + inc) & ((1 << 128) - 1)
    w[0], w[1] = st >> 64, st & _M64
    x = (w[0] ^ w[1]) & _M64
    rot = w[0] >> 58
    out = ((x >> rot) | (x << ((64 - rot) & 63))) & _M64
    return (out >> 11) * (1.0 / 9007199254740992.0)


if HAVE_NUMBA:
    from llvmlite import ir
    from numba.extending import intrinsic

    @intrinsic
    def _mulhi(typingctx, a, b):  # pragma: no cover - compiled
        """High 64 bits of the 128-bit product of two uint64 (one LLVM i128 multiply: the CPU's
        64x64->128 ``mul``; numba has no 128-bit integer type)."""
        sig = numba.types.uint64(numba.types.uint64, numba.types.uint64)

        def codegen(context, builder, signature, args):
            i128 = ir.IntType(128)
            p = builder.mul(builder.zext(args[0], i128), builder.zext(args[1], i128))
            return builder.trunc(builder.lshr(p, ir.Constant(i128, 64)), ir.IntType(64))

        return sig, codegen

    @numba.njit(cache=True, inline="always")
    def _output(hi, lo):  # pragma: no cover - compiled
        """PCG64's XSL-RR output of a state, as ``Generator.random()``'s double."""
        x = hi ^ lo
        rot = hi >> np.uint64(58)
        out = (x >> rot) | (x << ((np.uint64(64) - rot) & np.uint64(63)))
        return np.float64(out >> np.uint64(11)) * (1.0 / 9007199254740992.0)

    @numba.njit(cache=True, inline="always")
    def _affine(ah, al, sh, sl, ch, cl):  # pragma: no cover - compiled
        """(A * S + C) mod 2^128 on (hi, lo) uint64 pairs."""
        lo = sl * al
        hi = _mulhi(sl, al) + sl * ah + sh * al
        lo2 = lo + cl
        carry = np.uint64(1) if lo2 < lo else np.uint64(0)
        return hi + ch + carry, lo2

    @numba.njit(cache=True)
    def jump_table(w, m, out):  # pragma: no cover - compiled
        """``out[i] = (A_hi, A_lo, C_hi, C_lo)`` of ``i + 1`` advances (``A = M^(i+1)``,
        ``C = inc * (M^i + ... + 1)``) for i < m, for the increment of the words ``w``."""
        ah = np.uint64(MULT_HI)
        al = np.uint64(MULT_LO)
        ch = w[2]
        cl = w[3]
        for i in range(m):
            out[i, 0] = ah
            out[i, 1] = al
            out[i, 2] = ch
            out[i, 3] = cl
            # A <- M * A, C <- M * C + inc
            ah, al = _affine(np.uint64(MULT_HI), np.uint64(MULT_LO), ah, al, np.uint64(0), np.uint64(0))
            ch, cl = _affine(np.uint64(MULT_HI), np.uint64(MULT_LO), ch, cl, w[2], w[3])

    @numba.njit(cache=True, inline="always")
    def draw_at(w, table, j):  # pragma: no cover - compiled
        """The ``j``-th double (0-based) that ``Generator.random()`` would draw from the words
        ``w`` (not advanced): the output of state ``A_(j+1) * s + C_(j+1)``."""
        hi, lo = _affine(table[j, 0], table[j, 1], w[0], w[1], table[j, 2], table[j, 3])
        return _output(hi, lo)

    @numba.njit(cache=True, inline="always")
    def jump(w, table, m):  # pragma: no cover - compiled
        """Advance the words ``w`` by ``m`` draws (``m`` >= 1, at most the table's length)."""
        hi, lo = _affine(table[m - 1, 0], table[m - 1, 1], w[0], w[1], table[m - 1, 2], table[m - 1, 3])
        w[0] = hi
        w[1] = lo


__all__ = ["MULT_HI", "MULT_LO", "next_double_py", "store", "supported", "words"] + (
    ["draw_at", "jump", "jump_table"] if HAVE_NUMBA else [])
