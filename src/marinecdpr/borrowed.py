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

from numba import njit
from numba.core import cgutils, types
from numba.extending import intrinsic

__all__ = ["borrowed", "borrowed_first", "store", "load", "stored_size", "call_step", "call_stored", "data_address",
           "float64_pointer", "c_function", "kept_words", "stored", "store_in", "with_function"]


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


# ------------------------------------------------------------------ functions by address
@intrinsic
def call_stored(typingctx, function, args):
    """Call the C function at address ``function`` as ``int64 f(*args, void*)``: numba's C
    wrapper of a compiled function (:func:`c_function`) whose arguments are ``args`` (a tuple
    of integers and floats: addresses, indices, times) and one type reference last, passed
    as null."""
    from llvmlite import ir

    if not isinstance(args, types.BaseTuple) or not all(isinstance(a, (types.Integer, types.Float)) for a in args):
        return None

    def codegen(context, builder, signature, llargs):
        arg_tys = [context.get_value_type(t) for t in signature.args[1]]
        fnty = ir.FunctionType(ir.IntType(64), arg_tys + [cgutils.voidptr_t])
        fn = builder.inttoptr(llargs[0], fnty.as_pointer())
        values = [builder.extract_value(llargs[1], i) for i in range(len(arg_tys))]
        return builder.call(fn, values + [cgutils.get_null_value(cgutils.voidptr_t)])

    return types.int64(types.intp, args), codegen


@intrinsic
def data_address(typingctx, array):
    """The address of ``array``'s first element, as an integer (intp)."""
    if not isinstance(array, types.Array):
        return None

    def codegen(context, builder, signature, args):
        data = context.make_array(signature.args[0])(context, builder, value=args[0]).data
        return builder.ptrtoint(data, cgutils.intp_t)

    return types.intp(array), codegen


@intrinsic
def float64_pointer(typingctx, address):
    """The address ``address`` (an integer) as a pointer to float64, for ``numba.carray``."""

    def codegen(context, builder, signature, args):
        from llvmlite import ir

        return builder.inttoptr(args[0], ir.DoubleType().as_pointer())

    return types.CPointer(types.float64)(types.intp), codegen


_C_FUNCTIONS: dict = {}


def c_function(dispatcher, sig) -> int:
    """The address of numba's C wrapper of ``dispatcher`` compiled for ``sig`` (compiled, or
    loaded from the disk cache, once; its code kept alive here): what :func:`call_stored`
    and :func:`call_step` call."""
    key = (dispatcher, sig)
    if key not in _C_FUNCTIONS:
        cres = dispatcher.get_compile_result(sig)
        _C_FUNCTIONS[key] = (cres, cres.library.get_pointer_to_function(cres.fndesc.llvm_cfunc_wrapper_name))
    return _C_FUNCTIONS[key][1]


class _Keeping(bytearray):
    """A buffer that holds a reference to ``owner``: an array over it keeps the owner alive."""

    owner: object = None


def kept_words(n: int, owner: object):
    """n int64 words (zeros) whose memory keeps ``owner`` (the records a stored record points
    into) alive for as long as the array, or an array or record that holds it, lives: a
    compiled record that holds the words keeps what they point to. ``owner`` must not hold
    the words (an array's reference to its buffer is outside Python's cycle collector)."""
    import numpy as np

    buffer = _Keeping(8 * n)
    buffer.owner = owner
    return np.frombuffer(buffer, dtype=np.int64)


def stored(record, *, lead: int = 0):
    """``record`` written (:func:`store`) into :func:`kept_words` after ``lead`` zero words:
    the words keep the record's arrays alive; the record is at the words' address plus 8
    ``lead`` bytes (:func:`load`)."""
    from numba import typeof

    words = kept_words(lead + -(-stored_size(typeof(record)) // 8), record)
    store_in(record, words[lead:])
    return words


@njit(cache=True)
def store_in(record, words):
    """:func:`store` called from Python: ``record`` written into the int64 array ``words``
    (compiled once per record type, with numba's disk cache: the package's types only)."""
    store(record, words)


def with_function(function, record, arg_types: tuple):
    """``record`` :func:`stored` after one word that holds the address of ``function``'s C
    wrapper (:func:`c_function`) compiled for ``arg_types`` and, last, the record's type (a
    type reference): int64 words that a compiled caller calls with :func:`call_stored`
    (``words[0]``, the words' address plus 8 first among the arguments)."""
    from numba import typeof

    words = stored(record, lead=1)
    words[0] = c_function(function, types.int64(*arg_types, types.TypeRef(typeof(record))))
    return words
