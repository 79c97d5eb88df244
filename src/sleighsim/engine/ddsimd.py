"""Vectors of doubles in numba: LLVM's <W x double> as a numba type, so that compiled code keeps one value of each of
W lanes (independent orbits) in one vector register and every arithmetic operation acts on all lanes at once
(AVX-512: a zmm register holds 8 doubles; LLVM splits wider vectors into several registers).

Why explicit vectors: numba's loop vectoriser does vectorise an inner loop over lanes, but re-checks aliasing and
trip counts at every entry of that loop and keeps accumulators in memory, and numba leaves LLVM's SLP vectoriser
off; with explicit vectors the accumulators of a dot product live in registers.

The operations are IEEE's, lane by lane, with no fast-math flags (no reassociation, no contraction): +, -, *, /,
unary - and the in-place forms (numba operator overloads for vector-vector and vector-double operands, the
double broadcast to every lane) and the fused multiply-add :func:`fma_codegen` (LLVM's llvm.fma.vWf64). So each
lane computes exactly what the same scalar code computes, and :mod:`sleighsim.engine.ddarith`'s pair arithmetic,
written for doubles, compiles unchanged for vectors. A width is carried by the type of a token, a tuple of W
doubles (``like``), or of a vector.
"""

from __future__ import annotations

import operator

from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic, models, overload, register_model


class F64Vec(types.Type):
    """W doubles in one LLVM vector."""

    def __init__(self, width: int):
        self.width = width
        super().__init__(name=f"f64x{width}")


@register_model(F64Vec)
class _F64VecModel(models.PrimitiveModel):
    def __init__(self, dmm, fe_type):
        super().__init__(dmm, fe_type, ir.VectorType(ir.DoubleType(), fe_type.width))


def _width(ty) -> int | None:
    """The width of a vector type or of a width token (a tuple of W doubles); None for anything else."""
    if isinstance(ty, F64Vec):
        return ty.width
    if isinstance(ty, types.UniTuple) and ty.dtype == types.float64:
        return ty.count
    return None


def _as_vector(builder, ty, value, width: int):
    """``value`` of numba type ``ty`` (a double or a vector) as a vector of ``width`` (a double in every lane)."""
    if isinstance(ty, F64Vec):
        return value
    vty = ir.VectorType(ir.DoubleType(), width)
    v = builder.insert_element(ir.Constant(vty, ir.Undefined), value, ir.Constant(ir.IntType(32), 0))
    return builder.shuffle_vector(v, v, ir.Constant(ir.VectorType(ir.IntType(32), width), [0] * width))


def vector_signature(*args):
    """The vector type of an operation on ``args`` (vectors of one width and doubles), or None."""
    widths = {t.width for t in args if isinstance(t, F64Vec)}
    if len(widths) != 1 or not all(isinstance(t, F64Vec) or t == types.float64 for t in args):
        return None
    return F64Vec(widths.pop())


def fma_codegen(context, builder, sig, args):
    """a b + c with one rounding in every lane (llvm.fma.vWf64), the doubles among the operands broadcast."""
    width = sig.return_type.width
    x, y, z = (_as_vector(builder, t, v, width) for t, v in zip(sig.args, args))
    fnty = ir.FunctionType(x.type, [x.type] * 3)
    return builder.call(cgutils.get_or_insert_function(builder.module, fnty, f"llvm.fma.v{width}f64"), [x, y, z])


def _binary(name: str):
    @intrinsic
    def op(typingctx, a, b):
        vt = vector_signature(a, b)
        if vt is None:
            return None

        def codegen(context, builder, sig, args):
            x, y = (_as_vector(builder, t, v, vt.width) for t, v in zip(sig.args, args))
            return getattr(builder, name)(x, y)

        return vt(a, b), codegen

    return op


_add, _sub, _mul, _div = (_binary(n) for n in ("fadd", "fsub", "fmul", "fdiv"))


@intrinsic
def _neg(typingctx, a):
    def codegen(context, builder, sig, args):
        return builder.fneg(args[0])

    return a(a), codegen


def _overload_binary(op, fn) -> None:
    def typer(a, b):
        if vector_signature(a, b) is not None:
            return lambda a, b: fn(a, b)
        return None

    overload(op)(typer)


for _ops, _fn in (((operator.add, operator.iadd), _add), ((operator.sub, operator.isub), _sub),
                  ((operator.mul, operator.imul), _mul), ((operator.truediv, operator.itruediv), _div)):
    for _op in _ops:  # a += b on a vector is a = a + b (vectors are values)
        _overload_binary(_op, _fn)


@overload(operator.neg)
def _neg_overload(a):
    if isinstance(a, F64Vec):
        return lambda a: _neg(a)
    return None


def _pointer(context, builder, aryty, ary, width: int):
    """A pointer to the first element of a 1-D array, as a pointer to a vector of ``width``."""
    data = context.make_array(aryty)(context, builder, ary).data
    return builder.bitcast(data, ir.PointerType(ir.VectorType(ir.DoubleType(), width)))


def _is_row(ty) -> bool:
    return isinstance(ty, types.Array) and ty.ndim == 1 and ty.dtype == types.float64 and ty.layout == "C"


@intrinsic
def load(typingctx, row, like):
    """The first W elements of a C-contiguous 1-D float64 array (W the width of ``like``) as a vector."""
    width = _width(like)
    if width is None or not _is_row(row):
        return None

    def codegen(context, builder, sig, args):
        return builder.load(_pointer(context, builder, sig.args[0], args[0], width), align=8)

    return F64Vec(width)(row, like), codegen


@intrinsic
def store(typingctx, row, v):
    """Write the vector v into the first W elements of a C-contiguous 1-D float64 array."""
    if not (isinstance(v, F64Vec) and _is_row(row)):
        return None

    def codegen(context, builder, sig, args):
        builder.store(args[1], _pointer(context, builder, sig.args[0], args[0], v.width), align=8)
        return context.get_dummy_value()

    return types.none(row, v), codegen


@intrinsic
def splat(typingctx, x, like):
    """The double x in every lane of a vector as wide as ``like``."""
    width = _width(like)
    if width is None or x != types.float64:
        return None

    def codegen(context, builder, sig, args):
        return _as_vector(builder, types.float64, args[0], width)

    return F64Vec(width)(x, like), codegen
