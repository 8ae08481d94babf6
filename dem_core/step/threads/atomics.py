"""Atomic operations on one element of an int64 array, for numba code on several threads.

numba has no CPU atomics, so these are LLVM's own instructions, emitted through
``numba.extending.intrinsic`` (the LLVM Language Reference, "atomicrmw", "cmpxchg", "load atomic",
"store atomic"; the C++11 memory model's orderings):

- ``fetch_add(a, i, v)``: a[i] += v as one indivisible step; returns the old value
  (sequentially consistent: every write before it is seen by a thread that reads its result);
- ``compare_exchange(a, i, expected, new)``: a[i] = new if a[i] == expected; True if it did
  (sequentially consistent);
- ``load_acquire(a, i)``: read a[i]; no later read or write moves before it, and the writes
  the releasing thread made before its ``store_release`` are seen after it;
- ``store_release(a, i, v)``: a[i] = v; no earlier read or write moves after it.

Besides ordering the threads, they stop the compiler from keeping a[i] in a register: a spin
loop over ``load_acquire`` re-reads memory every turn. ``a`` must be a C-contiguous int64
array; ``i`` is not bounds-checked.
"""
from __future__ import annotations

import platform

from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

__all__ = ["fetch_add", "compare_exchange", "load_acquire", "store_release", "yield_cpu",
           "spin_pause"]


def _pointer(context, builder, sig, args):
    """LLVM pointer to a[i] (``args`` = (a, i, ...))."""
    arr_t, idx_t = sig.args[0], sig.args[1]
    arr = context.make_array(arr_t)(context, builder, args[0])
    idx = context.cast(builder, args[1], idx_t, types.intp)
    return cgutils.get_item_pointer(context, builder, arr_t, arr, [idx], wraparound=False)


def _check(arr):
    if not (isinstance(arr, types.Array) and arr.dtype == types.int64 and arr.ndim == 1):
        raise TypeError(f"atomics: need a 1-d int64 array, got {arr}")


@intrinsic
def fetch_add(typingctx, arr, idx, val):
    _check(arr)

    def codegen(context, builder, sig, args):
        v = context.cast(builder, args[2], sig.args[2], types.int64)
        return builder.atomic_rmw("add", _pointer(context, builder, sig, args), v, "seq_cst")
    return types.int64(arr, idx, val), codegen


@intrinsic
def compare_exchange(typingctx, arr, idx, expected, new):
    _check(arr)

    def codegen(context, builder, sig, args):
        e = context.cast(builder, args[2], sig.args[2], types.int64)
        n = context.cast(builder, args[3], sig.args[3], types.int64)
        pair = builder.cmpxchg(_pointer(context, builder, sig, args), e, n, "seq_cst",
                               "seq_cst")
        return builder.extract_value(pair, 1)
    return types.boolean(arr, idx, expected, new), codegen


@intrinsic
def load_acquire(typingctx, arr, idx):
    _check(arr)

    def codegen(context, builder, sig, args):
        return builder.load_atomic(_pointer(context, builder, sig, args), "acquire", 8)
    return types.int64(arr, idx), codegen


@intrinsic
def store_release(typingctx, arr, idx, val):
    _check(arr)

    def codegen(context, builder, sig, args):
        v = context.cast(builder, args[2], sig.args[2], types.int64)
        builder.store_atomic(v, _pointer(context, builder, sig, args), "release", 8)
        return context.get_dummy_value()
    return types.none(arr, idx, val), codegen


@intrinsic
def yield_cpu(typingctx):
    """``sched_yield()`` (POSIX): give the core to another runnable thread, if any. For a
    spinning thread whose partner may be waiting for a core (more threads than cores)."""
    def codegen(context, builder, sig, args):
        fnty = ir.FunctionType(ir.IntType(32), [])
        fn = cgutils.get_or_insert_function(builder.module, fnty, "sched_yield")
        builder.call(fn, [])
        return context.get_dummy_value()
    return types.none(), codegen


_X86 = platform.machine().lower() in ("x86_64", "amd64", "i386", "i686")


@intrinsic
def spin_pause(typingctx):
    """x86 ``pause`` (nothing elsewhere): a spin-wait hint. It lets a spinning thread leave the
    core's execution units to the thread on its sibling hyperthread and avoids the memory-order
    flush when the awaited value changes (Intel's optimization manual, "spin-wait loops")."""
    def codegen(context, builder, sig, args):
        if _X86:      # LLVM's intrinsic: numba's LLVM has no inline-assembly parser
            fn = cgutils.get_or_insert_function(
                builder.module, ir.FunctionType(ir.VoidType(), []), "llvm.x86.sse2.pause")
            builder.call(fn, [])
        return context.get_dummy_value()
    return types.none(), codegen
