"""Arrays a compiled loop borrows, so that passing a record costs no reference counting.

numba counts references to every array it binds: each function argument, each inlined
call's parameter and each field read from a record increments the array's count with an
atomic instruction and decrements it afterwards. A record of records such as the
virtual prototype's ``Parts`` holds about seventy arrays, so every call that takes it
costs some 140 atomic operations. In the closed loop this was two thirds of an
exchange's time (4.9 us of it; 1.6 us without the atomics; measured on the 2-core CI
machine, 2026-12-01).

:func:`borrowed` returns the same record with every array's reference counter left out
(its ``meminfo`` is null, as for an array that ``numba.carray`` makes over foreign
memory): numba then skips the counting. The arrays' memory stays owned by the original
arrays, which the caller holds for the whole call, so a compiled function may use
borrowed arrays freely within the call but must not return or store them. Members that
are not arrays (a typed list) keep their counting: the record returned holds a reference.
"""

from __future__ import annotations

from numba.core import cgutils, types
from numba.extending import intrinsic

__all__ = ["borrowed", "borrowed_first", "store", "load", "stored_size", "call_step"]


def _strip(context, builder, ty, value, count=True):
    """``value`` of numba type ``ty`` with every array's meminfo (recursively) null; other
    counted members (a typed list) given a reference (``count``) or not."""
    if isinstance(ty, types.Array):
        array = context.make_array(ty)(context, builder, value=value)
        array.meminfo = cgutils.get_null_value(array.meminfo.type)
        array.parent = cgutils.get_null_value(array.parent.type)
        return array._getvalue()
    if isinstance(ty, types.BaseTuple):
        out = value
        for i, item_ty in enumerate(ty):
            item = builder.extract_value(value, i)
            out = builder.insert_value(out, _strip(context, builder, item_ty, item, count), i)
        return out
    # anything else counted (a typed list, ...) is passed on as it is: the result is a new
    # reference, which numba releases at the end of its scope, so it takes one
    if count:
        context.nrt.incref(builder, ty, value)
    return value


@intrinsic
def borrowed(typingctx, record):
    """``record`` (an array, or a tuple or named tuple of arrays, numbers and such records)
    with its arrays borrowed: no reference counting where they are passed or read. Use
    inside a compiled function only, on arguments that outlive the call."""

    def codegen(context, builder, signature, args):
        return _strip(context, builder, signature.args[0], args[0])

    return record(record), codegen



@intrinsic
def borrowed_first(typingctx, held):
    """The first item of a typed list ``held``, borrowed (:func:`borrowed`): read in place,
    without the reference count of each of its arrays that ``held[0]`` takes. The list must
    hold an item and outlive the call."""
    item_ty = held.item_type

    def codegen(context, builder, signature, args):
        from llvmlite import ir
        from numba.typed.listobject import _container_get_data, ll_list_type

        fnty = ir.FunctionType(cgutils.voidptr_t, [ll_list_type])
        fn = cgutils.get_or_insert_function(builder.module, fnty, "numba_list_base_ptr")
        base = builder.call(fn, [_container_get_data(context, builder, signature.args[0], args[0])])
        ptr = builder.bitcast(base, context.get_data_type(item_ty).as_pointer())
        item = context.data_model_manager[item_ty].load_from_data_pointer(builder, ptr)
        return _strip(context, builder, item_ty, item)

    return item_ty(held), codegen


# ------------------------------------------------------------------ records by address
def stored_size(ty) -> int:
    """Bytes a value of numba type ``ty`` takes where :func:`store` writes it."""
    from numba.core.registry import cpu_target

    ctx = cpu_target.target_context
    return int(ctx.get_abi_sizeof(ctx.get_value_type(ty)))


@intrinsic
def store(typingctx, record, words):
    """Write ``record`` (as :func:`borrowed`: arrays without their counting; a typed list's
    pointer without a reference) into the int64 array ``words``, which must hold
    :func:`stored_size` bytes of the record's type. What is written points into the record's
    arrays and lists: valid while they live. Read it back with :func:`load`."""

    def codegen(context, builder, signature, args):
        ty = signature.args[0]
        value = _strip(context, builder, ty, args[0], count=False)
        data = context.make_array(signature.args[1])(context, builder, value=args[1]).data
        builder.store(value, builder.bitcast(data, context.get_value_type(ty).as_pointer()))
        return context.get_dummy_value()

    return types.none(record, words), codegen


@intrinsic
def load(typingctx, address, record_type):
    """The record of type ``record_type`` (a type reference) that :func:`store` wrote at
    ``address`` (an integer), borrowed (:func:`borrowed`). The memory it points into must
    outlive the call."""
    ty = record_type.instance_type

    def codegen(context, builder, signature, args):
        ptr = builder.inttoptr(args[0], context.get_value_type(ty).as_pointer())
        return _strip(context, builder, ty, builder.load(ptr))

    return ty(types.intp, record_type), codegen


@intrinsic
def call_step(typingctx, function, k, h, part, bus):
    """Call the C function at address ``function`` as ``int64 f(int64 k, double h, intp part,
    intp bus, void*, void*)``: a part's step compiled for its record's type
    (:func:`marinecdpr.prototype.parts.step_pointer`: numba's C wrapper of a compiled
    function whose last two arguments are type references, passed as null)."""
    from llvmlite import ir

    def codegen(context, builder, signature, args):
        i64, void_p = ir.IntType(64), cgutils.voidptr_t
        fnty = ir.FunctionType(i64, [i64, ir.DoubleType(), cgutils.intp_t, cgutils.intp_t, void_p, void_p])
        fn = builder.inttoptr(args[0], fnty.as_pointer())
        null = cgutils.get_null_value(void_p)
        return builder.call(fn, [args[1], args[2], args[3], args[4], null, null])

    return types.int64(types.intp, types.int64, types.float64, types.intp, types.intp), codegen
