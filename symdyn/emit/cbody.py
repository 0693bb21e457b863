"""The third stage of the C emitter: a reduced function (:mod:`symdyn.emit.cplan`) laid out as
the lines of a C body, printed with :class:`~symdyn.emit.cprinter.CPrinter`, its loops rendered
from the macros of ``templates/c_loops.j2``.

Two forms of one body: the scalar function (early returns on a singular mass matrix or a result
out of range) and the lanes function of the batch form (``vector``: GCC/Clang vector types, the
checks gathered in the mask ``ok``).
"""

from __future__ import annotations

import bisect
import contextlib
import functools
import re
from collections import Counter
from dataclasses import dataclass, field

import sympy as sp

from ..derive import articulated_loops as al
from .cplan import CORIOLIS_ARRAYS, FunctionPlan, ReducedPlan, tangent_width
from .cprinter import CPrinter, VectorUnsupported, count_operations, fused_sum
from .emission import fold_constants, template_environment
from ..model.outputs import CONTACT_SOLVED, STATUS_CODES

#: rows of L computed together by the looped LDL^T (independent sums for the pipeline)
ROWS = 4


@dataclass
class BodyContext:
    """What the layout of one function depends on besides its statements: the C names of the
    symbols (inputs, parameters, statements), the sin/cos arguments computed in one block at
    the top, the types (``internal``: the arithmetic; ``scalar``: the arguments' type;
    ``local_type``: the locals' C type) and the pivot tolerance."""

    prefix: str
    names: dict
    angles: list
    internal: str
    scalar: str
    local_type: str
    real: str
    n: int
    rtol: float
    #: entries of each input that has not ``n`` (a floating base's q: n + 1)
    sizes: dict = field(default_factory=dict)
    #: scratch arrays the body is handed by its caller (a pointer parameter) instead of
    #: declaring them: a stage of a staged function (symdyn.emit.cgen)
    given_arrays: frozenset = frozenset()
    #: every sum of products printed with the fused multiply-add macro (:func:`fma_macro`), not
    #: only the loops': the stages of the forward-dynamics derivatives and the long bodies
    #: (symdyn.emit.cgen.FUSE_FROM_STATEMENTS)
    fused: bool = False
    #: a floating base's quaternions as the body reads them (q's, and q1's): per configuration the
    #: local array (:data:`QUATERNION`, ``quat_u1``) and the C text of its four input entries,
    #: divided at the top of the body by the largest magnitude among them
    #: so that no square of a component underflows or overflows (any nonzero scale, subnormal
    #: to 1e308, gives the same rotation); empty when the body does not read it
    quaternion: tuple = ()

    def size(self, group: str) -> int:
        """The entries of input ``group``."""
        return self.sizes.get(group, self.n)


@dataclass
class Body:
    """The lines of a body, its operation counts, the symbols it reads and the vector math
    functions it calls (lanes form)."""

    lines: list[str]
    ops: Counter
    used: set
    vector_functions: set = field(default_factory=set)
    #: the parts a long body is split into (:data:`SPLIT_FROM_STATEMENTS`): each ``(returns,
    #: extra parameters, lines)``, a function of its own called in order from ``lines``
    parts: list = field(default_factory=list)
    #: ``(name, entries)`` of each scratch array of :attr:`BodyContext.given_arrays` it uses
    given: list = field(default_factory=list)
    #: whether it calls the fused multiply-add macros (templates/fma.j2 must define them)
    fma: bool = False


@functools.lru_cache(maxsize=1)
def _loops():
    """The macros of ``templates/c_loops.j2`` (loaded once per process)."""
    return template_environment().get_template("c_loops.j2").module


def _macro_lines(text) -> list[str]:
    text = str(text)
    return text[:-1].split("\n") if text.endswith("\n") else text.split("\n")


def gram_loop(out: str, size: int, ltype: str, element_bytes: int, prefix: str, vector: bool) -> list[str]:
    """C lines of ``out[i][j] = out[j][i] = S_i . F_j`` (i < j, ``out`` row-major size x size)
    from ``mass_s`` (component k of S_i at ``mass_s[k * (size - 1) + i]``, so consecutive i are
    contiguous) and ``mass_f`` (F_j's 6 components at ``mass_f + 6 * (j - 1)``).

    Every entry is ``s0*f0 + s1*f1 + ... + s5*f5`` in this order, however it is computed (same
    results).  The plain loop runs over row j left of the diagonal (contiguous in ``out`` and
    ``mass_s``): gcc -O3 vectorizes it, gcc -O2 does not.  So where the compiler has GCC/Clang
    vector types over SSE2, AVX or NEON (``PREFIX_GRAM_BYTES``, see the helpers), the scalar
    function computes two rows at a time over vectors of consecutive i, each load of S serving
    both rows.  Generic 24-joint chain, D: gcc -O2 1400 -> 1245 ns; gcc -O3 -march=native about
    the same as its own vectorization of the plain loop (1240-1270 ns).  ``vector``: the lanes
    function of the batch form, where every value is already a vector over states (plain loop).
    The entries above the diagonal are written lane by lane: gcc -O2 keeps a loop over the
    lanes otherwise (1240 -> 1340 ns at 24 joints)."""
    return _macro_lines(_loops().gram_loop(out, size, ltype, element_bytes, prefix, vector))


def gram_ops(size: int) -> Counter:
    """Operations of :func:`gram_loop`: six products and five sums per entry above the diagonal."""
    return Counter({"mul": 6 * size * (size - 1) // 2, "add": 5 * size * (size - 1) // 2})


def coriolis_loop(out: str, n: int, ltype: str, store: str, prefix: str, vector: bool) -> list[str]:
    """C lines of the Coriolis matrix ``out`` (row-major n x n) from the factor arrays of
    :data:`symdyn.emit.cplan.CORIOLIS_ARRAYS` (component c of vector k at ``[c * n + k]``):
    ``out[i][k] = S_i . F_k`` for k >= i, ``g_i . dS_k + e_i . S_k`` for k < i, each row's
    inner loops over consecutive k (contiguous in ``out`` and the arrays).  gcc -O3 vectorizes
    the plain loops, gcc -O2 does not: where the compiler has vector types
    (``PREFIX_GRAM_BYTES``, as for :func:`gram_loop`) they run over vectors of consecutive k,
    each entry summed in the plain loop's order.  ``store``: the cast to the output type, or
    empty (a cast, or ``vector``, the batch form's lanes function, keeps the plain loop)."""
    return _macro_lines(_loops().coriolis_loop(out, n, ltype, store, prefix, vector))


def coriolis_ops(n: int) -> Counter:
    """Operations of :func:`coriolis_loop`: 6 products and 5 sums per entry on and above the
    diagonal, 12 and 11 below."""
    upper, lower = n * (n + 1) // 2, n * (n - 1) // 2
    return Counter({"mul": 6 * upper + 12 * lower, "add": 5 * upper + 11 * lower})


def looped_solve(n: int, ltype: str, rtol: str, one: str, vector: bool, out_name: str, store: str,
                 internal: str, scalar: str, prefix: str) -> tuple[list[str], Counter]:
    """C lines solving ``fd_M qdd = fd_b`` by an LDL^T loop (M's lower triangle given, L
    written over it), with the same pivot and finiteness checks as the unrolled
    form: status SINGULAR when a pivot ``d_j`` is not above ``rtol * M_jj``, NOT_FINITE when a
    result is not finite (:func:`status_macros`); qdd is written only on success.  ``vector``:
    the lanes function's form (checks gathered in ``all_ok``, ``*ok`` set).  Returns the lines
    and their operation counts."""
    limit, fabs = _limit(internal, scalar)
    lines = _macro_lines(_loops().looped_solve(n, ltype, rtol, one, vector, out_name, store, ROWS, limit, fabs,
                                               status_macros(prefix)))
    mul = add = div = 0
    for j in range(n):
        div += 1
        mul += 2 * j + (n - 1 - j) * (j + 1)  # w and d; column j of L
        add += j + (n - 1 - j) * j
    mul += n * (n - 1) // 2 + n + n * (n - 1) // 2  # the two substitutions
    add += n * (n - 1)
    return lines, Counter({"mul": mul, "add": add, "div": div})


def status_macros(prefix: str) -> dict[str, str]:
    """The header's name of each status code (:data:`symdyn.model.outputs.STATUS_CODES`):
    ``{"SINGULAR": "PUMA560_SINGULAR", ...}``."""
    return {name: f"{prefix.upper()}_{name}" for name in STATUS_CODES}


def pivot_rtol_macro(prefix: str) -> str:
    """The header's pivot tolerance macro (its default per precision, overridable)."""
    return f"{prefix.upper()}_PIVOT_RTOL"


def fma_macro(prefix: str) -> str:
    """The name of the fused multiply-add macro of a generated file (``templates/fma.j2``):
    ``fma`` where the target has a fast one (``FP_FAST_FMA``), else ``c + a*b``; its twin
    ``PREFIX_FMA_NEG`` is ``c - a*b``."""
    return f"{prefix.upper()}_FMA"


def product_loop(products, store: str, internal: str, scalar: str, fma: str, prefix: str) -> tuple[list[str], Counter]:
    """C lines forming the forward-dynamics derivatives ``-Minv dtau/dx`` from the scratch arrays
    (``products``: a :attr:`FunctionPlan.products`), checking every result and writing the
    outputs, ending with ``return 0``; and their operation counts.  Each row of a result is one
    loop over the scratch rows' entries (padding included), its n terms fused by ``fma``: the
    rows are independent, which the processor overlaps (one loop over i, k and j chains them);
    or, where dtau/dx has enough structural zeros, by columns (:func:`_column_products`)."""
    n, blocks, minv, stride, columns = products
    limit, fabs = _limit(internal, scalar)
    if columns is not None:
        return _column_products(products, store, limit, fabs, _exponent_bits(internal, scalar), fma, prefix)
    rows = []
    for b, (array, _) in enumerate(blocks):
        for i in range(n):
            terms = [(True, f"fdd_m[{i * n + k}]", f"{array}[{k * stride} + j]") for k in range(n)]
            rows.append((b * n * stride + i * stride, fused_sum(terms, fma)))
    lines = _macro_lines(_loops().inverse_products(n, stride, stride, blocks, minv, rows, store, limit, fabs,
                                                   _exponent_bits(internal, scalar), status_macros(prefix), False))
    return lines, Counter({"mul": len(blocks) * n * n * stride, "add": len(blocks) * n * (n - 1) * stride})


def _column_products(products, store: str, limit: str, fabs: str, bits, fma: str, prefix: str) -> tuple[list[str], Counter]:
    """:func:`product_loop` by columns (:func:`symdyn.emit.cplan.product_columns`): column j of
    each result, ``-sum_k M^-1 row k * dtau/dx_kj`` over the rows k where dtau/dx's column j is
    not identically zero (M^-1 is symmetric: its row k is its column k), one loop over the n
    entries of the column, stored transposed (``fdd_r`` column-major, n x n per block)."""
    n, blocks, minv, stride, columns = products
    rows, mul, add = [], 0, 0
    for b, ((array, _), block) in enumerate(zip(blocks, columns)):
        for j, nonzero in enumerate(block):
            terms = [(True, f"fdd_m[{k * n} + i]", f"{array}[{k * stride + j}]") for k in nonzero]
            rows.append((b * n * n + j * n, fused_sum(terms, fma) if terms else "0"))
            mul, add = mul + n * len(nonzero), add + n * max(len(nonzero) - 1, 0)
    lines = _macro_lines(_loops().inverse_products(n, stride, n, blocks, minv, rows, store, limit, fabs, bits,
                                                   status_macros(prefix), True))
    return lines, Counter({"mul": mul, "add": add})


def contact_product_loop(products, store: str, internal: str, scalar: str, fma: str, prefix: str) -> tuple[list[str], Counter]:
    """C lines forming W's columns ``M^-1[:, c] + sum_l U[:, l] V[c, l]`` and then the contact
    derivatives ``-W dF`` (``products``: a :class:`~symdyn.emit.cplan.ContactProducts`) column by
    column, each column one loop over the padded rows (the terms: V's nonzero entries of the
    column, dF's nonzero rows; fused by ``fma``), checking every result, the solution and W, and
    writing the outputs, ending with ``return 0``; and their operation counts (every lane the loops
    run)."""
    n, m, stride = products.n, products.m, products.stride
    limit, fabs = _limit(internal, scalar)
    forming, mul, add = [], 0, 0
    for c, nonzero in enumerate(products.forming):
        terms = ([(False, "", f"cdd_m[{c * stride} + i]")] if c < n else []) + [
            (False, f"cdd_u[{l * stride} + i]", f"cdd_t[{c * m + l}]") for l in nonzero]
        forming.append((c * stride, fused_sum(terms, fma) if terms else "0"))
        mul, add = mul + stride * len(nonzero), add + stride * max(len(terms) - 1, 0)
    columns = []
    for b, (_, array, nonzero_rows) in enumerate(products.blocks):
        for j, nonzero in enumerate(nonzero_rows):
            terms = [(True, f"cdd_w[{k * stride} + i]", f"{array}[{k * n + j}]") for k in nonzero]
            columns.append(((b * n + j) * stride, fused_sum(terms, fma) if terms else "0"))
            mul, add = mul + stride * len(nonzero), add + stride * max(len(nonzero) - 1, 0)
    checked = [("cdd_r", len(products.blocks) * n * stride), ("cdd_w", products.rows * stride),
               ("cdd_a", products.rows)]
    lines = _macro_lines(_loops().contact_products(stride, forming, columns, checked, products.writes, store, limit,
                                                   fabs, _exponent_bits(internal, scalar), status_macros(prefix)))
    return lines, Counter({"mul": mul, "add": add})


def tangent_loops(tangent, printer, store: str, fma: str) -> tuple[list[str], Counter, int]:
    """C lines of a :class:`~symdyn.emit.cplan.TangentPlan`: each step a loop over the
    directions (``dv_t``, one row of :func:`tangent_width` entries per live tangent, rows reused
    once their last reader has run), its terms fused by the macro ``fma``, each derivative row
    copied to its destination as soon as it is computed.  Returns the lines, their operation
    counts (every lane the loops run) and the rows of ``dv_t`` they need."""
    tangents, n = tangent.tangents, tangent.tangents.directions
    width = tangent_width(n)
    steps = tangents.steps_of(tangent.groups)
    destination = {}  # tangent id -> (destination, row, stride)
    zero_rows = []
    for group, dest, stride in zip(tangent.groups, tangent.destinations, tangent.strides):
        for row, source in enumerate(tangents.rows[group]):
            if source is None:
                zero_rows.append((dest, row, stride))
            else:
                destination[source] = (dest, row, stride)
    last = {}
    for k, step in enumerate(steps):
        for source, _ in step.terms:
            last[source] = k
    free, rows, slot = [], 0, {}
    lines: list[str] = []
    ops = Counter()
    zero = printer.literal(0.0)

    def coefficient(value) -> tuple[int, str]:
        """(sign, printed factor or "" for 1) of a coefficient."""
        if value.is_number:  # one literal: a printed constant expression after a sign is not an operand
            number = float(fold_constants(value))
            sign = -1 if number < 0 else 1
            return sign, "" if abs(number) == 1 else printer.literal(abs(number))
        index, sign = tangent.coefficients[value]
        return sign, f"dv_p[{index}]"

    for k, step in enumerate(steps):
        if free:
            target = free.pop()
        else:
            target, rows = rows, rows + 1
        terms = []
        for source, value in step.terms:
            sign, factor = coefficient(value)
            terms.append((sign < 0, factor, f"dv_t[{slot[source] * width} + j]"))
            ops["mul"] += width if factor else 0
        text = fused_sum(terms, fma)
        ops["add"] += width * max(0, len(step.terms) - 1) + len(step.direct)
        direct = []
        for direction, value in step.direct:
            sign, factor = coefficient(value)
            direct.append((direction, f"-{factor or printer.literal(1.0)}" if sign < 0 else factor or printer.literal(1.0)))
        lines += _macro_lines(_loops().tangent_step(target * width, width, text or zero, direct))
        for source, _ in step.terms:
            if last[source] == k:
                free.append(slot[source])
        slot[step.target] = target
        if step.target in destination:
            dest, row, stride = destination[step.target]
            lines += _macro_lines(_loops().tangent_row(dest, row, stride, target * width, store, zero))
            if step.target not in last:
                free.append(target)
    for dest, row, stride in zero_rows:
        lines += _macro_lines(_loops().tangent_row(dest, row, stride, None, store, zero))
    return lines, ops, rows


def _step_lines(program, outputs, bindings: dict, printer: CPrinter, ltype: str, after: dict | None = None):
    """The C lines of one step of the articulated-body loops: its inputs bound to array entries
    (``bindings``: input symbol -> C expression; only those the step reads), its statements, and
    after the statement defining a symbol of ``after`` the lines given there (the pivot check).
    Returns the lines and the step's operation counts."""
    statements = program.needed_for(list(outputs))
    read = set().union(*(sp.sympify(e).free_symbols for e in outputs), *(rhs.free_symbols for _, rhs in statements))
    lines = [f"const {ltype} {printer.names[symbol]} = {source};" for symbol, source in bindings.items() if symbol in read]
    ops: Counter = Counter()
    for symbol, rhs in statements:
        lines.append(f"const {ltype} {printer.names[symbol]} = {printer.doprint(rhs)};")
        ops += count_operations(rhs)
        lines += (after or {}).get(symbol, [])
    return lines, ops


#: the articulated-body loops' sums of products use the fused multiply-add macro: gcc -O3
#: -march=native on the AMD EPYC, generic chains: 1123 -> 894 ns at 12 joints, 4670 -> 3704 ns
#: at 48 (the plain loops were slower there than at -O2 without -march=native); at -O2 for
#: x86-64's baseline the macro is the plain sum (same bits)
FUSED_ARTICULATED_LOOPS = True


def articulated_body_loops(loops, printer: CPrinter, ltype: str, out_name: str, store: str, internal: str,
                           scalar: str, prefix: str, fma: str = "") -> tuple[list[str], Counter]:
    """C lines of forward dynamics by the articulated-body algorithm as three loops over the
    joints (:class:`symdyn.derive.articulated_loops.ArticulatedLoops`): a ``static const`` table
    of the joints' constants, the velocity loop (base to tip), the backward loop (tip to joint
    2, then joint 1's pivot), the acceleration loop; ``fd_c``, ``fd_s`` (cos, sin of the joint
    angles) and ``fd_t`` (tau less friction) are given.  Status 1 when a pivot ``d_j`` is not
    positive (checked before the division by it), 2 when a result is not finite; qdd is written
    only on success.  Returns the lines and their operation counts (each step's times its trips)."""
    n = loops.n
    names = dict(printer.names)
    for program in (loops.velocity, loops.backward, loops.acceleration):
        names.update((symbol, symbol.name) for symbol, _ in program.assignments)
    for group in (loops.slots, al.COS_SIN, (al.QD, al.TAU, al.SCALED_FORCE), al.PARENT_VELOCITY, al.VELOCITY,
                  al.BIAS_ACCEL, al.CARRIED_INERTIA, al.CARRIED_FORCE, al.GAIN, al.PARENT_ACCEL):
        names.update((symbol, symbol.name) for symbol in group)
    local = CPrinter(names, printer.precision, fma=fma)

    def entries(symbols, array: str, offset: str = "") -> dict:
        return {symbol: f"{array}[{offset}{i}]" for i, symbol in enumerate(symbols)}

    joint = {**entries(loops.slots, "fd_table[j]"), al.COS_SIN[0]: "fd_c[j]", al.COS_SIN[1]: "fd_s[j]"}
    pivot = loops.backward_outputs[0]
    status = status_macros(prefix)
    check = {pivot: [f"if (!({pivot.name} > 0)) {{", f"    return {status['SINGULAR']};", "}"]}
    backward_inputs = {**joint, al.TAU: "fd_t[j]", **entries(al.VELOCITY, "fd_v", "6 * j + 6 + "),
                       **entries(al.BIAS_ACCEL, "fd_z", "6 * j + "), **entries(al.CARRIED_INERTIA, "fd_K"),
                       **entries(al.CARRIED_FORCE, "fd_k")}
    steps = {
        "velocity": (loops.velocity, loops.velocity_outputs,
                     {**joint, al.QD: "qd[j]", **entries(al.PARENT_VELOCITY, "fd_v", "6 * j + ")}, None),
        "backward": (loops.backward, loops.backward_outputs, backward_inputs, check),
        "base": (loops.backward, loops.backward_outputs[:8], backward_inputs, check),  # d, b, ud: all joint 1 needs
        "acceleration": (loops.acceleration, loops.acceleration_outputs,
                         {**joint, **entries(al.BIAS_ACCEL, "fd_z", "6 * j + "), **entries(al.GAIN, "fd_g", "6 * j + "),
                          al.SCALED_FORCE: "fd_ud[j]", **entries(al.PARENT_ACCEL, "fd_a")}, None)}
    printed, ops = {}, Counter()
    trips = {"velocity": n, "backward": n - 1, "base": 1, "acceleration": n}
    for name, (program, outputs, bindings, after) in steps.items():
        lines, step_ops = _step_lines(program, outputs, bindings, local, ltype, after)
        results = [local.doprint(e) for e in outputs]
        for e in outputs:
            step_ops += count_operations(e)
        printed[name] = (lines, results)
        ops += Counter({kind: count * trips[name] for kind, count in step_ops.items()})
    limit, fabs = _limit(internal, scalar)
    table = [", ".join(local.literal(v) for v in row) for row in loops.table]
    lines = _macro_lines(_loops().articulated_loops(
        n, ltype, table, max(1, len(loops.slots)), printed, [local.doprint(sp.sympify(g)) for g in loops.gravity],
        out_name, store, limit, fabs, status))
    return lines, ops


def _limit(internal: str, scalar: str) -> tuple[str, str]:
    """The largest finite result and the absolute-value function, in the arithmetic the results
    are computed in (compared there)."""
    if internal == "double":
        return ("(double)FLT_MAX" if scalar == "float" else "DBL_MAX"), "fabs"
    return "FLT_MAX", "fabsf"


def _exponent_bits(internal: str, scalar: str) -> tuple[str, str, str] | None:
    """``(unsigned type, exponent mask, floating type)`` of the arithmetic the results are
    computed in, for the product loop's test of finite results by their bits; None where they
    are stored in a narrower type (double computed, float stored: the test is against FLT_MAX)."""
    if internal != scalar:
        return None
    return ("uint64_t", "UINT64_C(0x7ff0000000000000)", "double") if internal == "double" else \
        ("uint32_t", "UINT32_C(0x7f800000)", "float")


def _position_of(expr, position) -> int:
    """Index of the last statement ``expr`` reads (-1: none)."""
    return max((position[x] for x in sp.sympify(expr).free_symbols if x in position), default=-1)


#: a scalar body of more statements than this is emitted as parts of at most about
#: :data:`PART_LINES` lines (:func:`_part_bounds`), each a function of its own (not inlined, where
#: the compiler has the attribute), the values one part hands to a later one kept in an array,
#: each stored right after it is computed and loaded again just before its first use in a later
#: part: gcc's register allocation grows faster than linearly with a function's length and its
#: basic-block vectorizer's memory with the square of the memory accesses in one block (gcc -O2
#: on TIAGo's floating-base Coriolis matrix in one function: 40 s and 548 MB, 30 s of the file's
#: 52 in LRA's hard register assignment; in parts of 600 lines 3.8 s and 168 MB, and faster:
#: 8118 -> 7197 ns, TALOS reduced 4716 -> 4117 ns; docs/benchmarks.md, "Parts by lines, values
#: carried where used");
#: the results are the same bit for bit.  Below the limit a body stays whole: TALOS's inverse
#: dynamics (1541 statements) runs fastest in one piece that fits the instruction cache.
SPLIT_FROM_STATEMENTS = 2500
PART_LINES = 600
#: placeholders in a split body's calls, replaced by the emitter: the function's own arguments,
#: and ``@PART<k>@`` the name of part k
ARGUMENTS, PART = "@ARGS@", "@PART"

#: the local array of a floating base's scaled quaternion (:meth:`BodyWriter._quaternion_block`)
QUATERNION = "quat_u"

#: the status a task-space function returns at a singular task (J M^-1 J^T not positive definite)
TASK_SINGULAR = STATUS_CODES["TASK_SINGULAR"][0]
#: the name of each status code a check returns
STATUS_NAMES = {value: name for name, (value, _) in STATUS_CODES.items() if name != "CONTACT_SINGULAR"}


#: a function whose results hold more distinct values than this (twice the 16 vector registers of
#: x86-64) writes each result as soon as it is computed (:attr:`BodyWriter.early_outputs`):
#: written at the end, every one stays live through the whole body and is spilled.  TALOS's
#: mass matrix (about 680 values in 1444 entries): 1373 -> 1061 ns at gcc -O3 -march=native,
#: 1684 -> 1438 ns at -O2.  The 6- and 7-joint arms' functions past the limit (their Coriolis
#: matrices and Jacobians) moved by -4% to +4% in an A/B in one binary, as much as identical
#: functions moved by code placement; with 7 to 28 values (the arms' inverse dynamics and mass
#: matrices) writing early was as often slower as faster (docs/benchmarks.md, "Results written
#: as soon as computed")
EARLY_OUTPUTS_FROM = 32


def writes_results_early(plan: FunctionPlan, reduced: ReducedPlan) -> bool:
    """Whether each result entry (and its mirror in a symmetric output) is written as soon as the
    statements it reads are computed, rather than all at the end: when more than
    :data:`EARLY_OUTPUTS_FROM` distinct result values would otherwise stay live to the end, in
    every function but those that check their results before writing them (forward dynamics,
    task space, the inverse mass matrix) or write them from scratch arrays (the looped solve,
    the products of the forward-dynamics derivatives)."""
    if plan.checked or plan.looped or plan.sweeps or plan.products or plan.contact_products:
        return False
    values = {expr for target, expr in zip(plan.targets, reduced.outputs)
              if not target.local and sp.sympify(expr).free_symbols}
    return len(values) > EARLY_OUTPUTS_FROM


class BodyWriter:
    """Lays out one reduced function as C lines (:meth:`write`)."""

    def __init__(self, plan: FunctionPlan, reduced: ReducedPlan, context: BodyContext, vector: bool):
        self.plan, self.reduced, self.ctx, self.vector = plan, reduced, context, vector
        prefix = context.prefix
        self.vreal = f"{prefix}_vreal"
        self.printer = CPrinter(context.names, context.internal, vector_prefix=prefix if vector else "",
                                fma=fma_macro(prefix) if context.fused and not vector else "")
        for k, arg in enumerate(context.angles):
            self.printer.trig[sp.sin(arg)] = f"trig_sin[{k}]"
            self.printer.trig[sp.cos(arg)] = f"trig_cos[{k}]"
        self.ltype = self.vreal if vector else context.local_type
        self.given: list[tuple[str, int]] = []  # the scratch arrays the caller hands over
        self.store = f"({context.real})" if context.internal != context.scalar else ""
        self.position = {sym: k for k, (sym, _) in enumerate(reduced.statements)}
        self.lines: list[str] = []
        self.ops: Counter = Counter()
        self.used: set = set()

    def show(self, expr) -> str:
        """The printed expression; in the lanes function a number is broadcast to every lane."""
        text = self.printer.doprint(expr)
        if self.vector and not sp.sympify(expr).free_symbols:
            text = f"({self.vreal}){{0.0}} + {text}"
        return text

    def write(self) -> Body:
        plan, ctx = self.plan, self.ctx
        if plan.checked and not self.vector:
            self._input_checks()
        self._placed_writes()
        self.lines += number_writes(self.numbers, f"{ctx.prefix}_{plan.name}", self.vector)
        self._quaternion_block()
        self._trig_block()
        checks = self._pivot_checks()
        self.arrays: list[tuple[str, int]] = ([("trig_sin", len(ctx.angles)), ("trig_cos", len(ctx.angles))]
                                              if ctx.angles else []) + [(array, 4) for array, _ in ctx.quaternion]
        if plan.checked and self.vector:
            self.lines.append(f"{ctx.prefix}_vint all_ok = ({self.vreal}){{0.0}} == 0.0; /* every lane true */")
            limit, _ = _limit(ctx.internal, ctx.scalar)  # a lane whose input is NaN or infinite: the scalar function's 2
            self.lines.append("all_ok &= " + "\n        & ".join(
                f"({name}[{i}] <= {limit}) & ({name}[{i}] >= -{limit})" for name in plan.inputs
                for i in range(ctx.size(name))) + ";")
        if plan.gram:
            size = 6 * (plan.gram[1] - 1)
            self._declare([("mass_s", size), ("mass_f", size)])
        if plan.coriolis:
            self._declare([(a, 6 * plan.coriolis[1]) for a in CORIOLIS_ARRAYS])
        if plan.sweeps:
            if self.vector:
                raise VectorUnsupported("the articulated-body algorithm's loops")
            n = ctx.n
            self._declare([("fd_c", n), ("fd_s", n), ("fd_t", n), ("fd_v", 6 * n + 6), ("fd_z", 6 * n),
                           ("fd_g", 6 * n), ("fd_ud", n), ("fd_x", n)])
        if plan.looped:
            n = ctx.n
            self._declare([("fd_M", n * n), ("fd_b", n), ("fd_w", n), ("fd_d", n), ("fd_inv", n), ("fd_x", n)])
        if plan.tangents:
            if self.vector:
                raise VectorUnsupported("the derivatives' tangent loops")
            self.tangent_lines, tangent_ops, rows = tangent_loops(plan.tangents, self.printer, self.store, self._loop_fma())
            self.ops += tangent_ops
            width = tangent_width(plan.tangents.tangents.directions)
            self._declare(([("dv_p", plan.tangents.entries)] if plan.tangents.entries else [])
                          + [("dv_t", max(1, rows) * width)])
        if plan.products:
            if self.vector:
                raise VectorUnsupported("the forward-dynamics derivatives' product loop")
            n, blocks, _, stride, _ = plan.products
            self._declare([("fdd_m", n * n)] + [(array, n * stride) for array, _ in blocks]
                          + [("fdd_r", len(blocks) * n * stride)])
        if plan.contact_products:
            if self.vector:
                raise VectorUnsupported("the contact derivatives' product loop")
            cp = plan.contact_products
            self._declare([("cdd_m", cp.n * cp.stride), ("cdd_u", cp.m * cp.stride), ("cdd_t", cp.rows * cp.m),
                           ("cdd_w", cp.rows * cp.stride), ("cdd_a", cp.rows)]
                          + [(array, cp.rows * cp.n) for _, array, _ in cp.blocks]
                          + [("cdd_r", len(cp.blocks) * cp.n * cp.stride)])
        self.segment_start = len(self.lines)
        late = self._statements(checks)
        self.segment_end = len(self.lines)
        if plan.checked and not plan.looped and not plan.sweeps and not plan.products and not plan.contact_products:
            self._checked_results(late)
        else:
            for target, expr in late:
                text = self.show(expr)
                self.lines.append(f"{target.lvalue} = {self.store}({text});" if self.store and not (plan.looped or plan.sweeps)
                                  else f"{target.lvalue} = {text};")
                self._count(expr)
        self._loops()
        if not self.early_outputs:
            self.lines.extend(f"{target} = {source};" for target, source in plan.aliases)
        body = Body(self.lines, self.ops, self.used, self.printer.vector_functions, given=self.given,
                    fma=bool(self._loop_fma()) and not self.vector)
        if not self.vector and len(self.reduced.statements) > SPLIT_FROM_STATEMENTS:
            late_symbols = set().union(*(sp.sympify(e).free_symbols for _, e in late))
            _split(self, body, late_symbols, PART_LINES)
        return body

    @functools.cached_property
    def early_outputs(self) -> bool:
        """:func:`writes_results_early` of this function."""
        return writes_results_early(self.plan, self.reduced)

    def _loop_fma(self) -> str:
        """The fused multiply-add macro of the loops, or "" for plain sums: fused in the
        forward-dynamics derivatives (their products, their stages) and in the fused bodies
        (:attr:`BodyContext.fused`, whose printer uses the same macro), plain in the
        inverse-dynamics derivatives' tangent loops, where fusing measured slower: a step's sum
        fused is a chain of FMAs, and an add has half an FMA's latency on current x86 cores
        (iiwa14's dtau/dq 391 -> 466 ns, gcc -O3 -march=native; docs/benchmarks.md)."""
        fused = (self.ctx.fused or self.plan.products or self.plan.contact_products
                 or (self.plan.sweeps is not None and FUSED_ARTICULATED_LOOPS))
        return fma_macro(self.ctx.prefix) if fused else ""

    def _declare(self, arrays) -> None:
        """Declare the scratch arrays ``[(name, size)]`` in one line (but those the caller hands
        over: :attr:`BodyContext.given_arrays`); :func:`_split` passes them to the parts of a
        long body."""
        given = self.ctx.given_arrays
        declared = [(name, size) for name, size in arrays if name not in given]
        if declared:
            self.lines.append(f"{self.ltype} " + ", ".join(f"{name}[{size}]" for name, size in declared) + ";")
        self.given += [(name, size) for name, size in arrays if name in given]
        self.arrays += arrays

    def _input_checks(self) -> None:
        """Forward dynamics first checks its inputs: a NaN or infinite q, qd or tau returns 2
        (not finite) before anything is computed, rather than a NaN pivot's 1 (singular)."""
        limit, fabs = ("FLT_MAX", "fabsf") if self.ctx.scalar == "float" else ("DBL_MAX", "fabs")
        by_size: dict[int, list[str]] = {}  # one loop per array length
        for name in self.plan.inputs:
            by_size.setdefault(self.ctx.size(name), []).append(name)
        for size, names in by_size.items():
            tests = "\n            || ".join(f"!({fabs}({name}[i]) <= {limit})" for name in names)
            self.lines += [f"for (int i = 0; i < {size}; ++i) {{",
                           f"    if ({tests}) {{",
                           f"        return {status_macros(self.ctx.prefix)['NOT_FINITE']};",
                           "    }",
                           "}"]

    def _count(self, expr) -> None:
        self.ops += count_operations(expr)
        self.used |= sp.sympify(expr).free_symbols

    def _quaternion_block(self) -> None:
        """A floating base's quaternion (each configuration's) divided by the largest magnitude
        of its components (a division each: the reciprocal of a subnormal scale would overflow),
        into ``quat_u`` (``quat_u1``): its rotation is the input's, and its squares are within
        [1, 4].  A zero quaternion gives NaN (a function with a status returns NAME_NOT_FINITE)."""
        if not self.ctx.quaternion:
            return
        if self.vector:
            raise VectorUnsupported("a floating base's quaternion scaling")
        fabs, fmax = ("fabsf", "fmaxf") if self.ctx.internal == "float" else ("fabs", "fmax")
        for array, entries in self.ctx.quaternion:
            magnitudes = [f"{fabs}({entry})" for entry in entries]
            self.lines += [f"{self.ltype} {array}[4];",
                           "{",
                           f"    const {self.ltype} quat_m = {fmax}({fmax}({magnitudes[0]}, {magnitudes[1]}), "
                           f"{fmax}({magnitudes[2]}, {magnitudes[3]}));",
                           *[f"    {array}[{k}] = {entry}/quat_m;" for k, entry in enumerate(entries)],
                           "}"]
            self.ops += Counter({"div": 4})

    def _trig_block(self) -> None:
        """The sines and cosines of the input angles, computed in one call at the top."""
        angles, ctx = self.ctx.angles, self.ctx
        if not angles:
            return
        self.used |= set().union(*(a.free_symbols for a in angles))
        helper = f"{ctx.prefix}_vsincos" if self.vector else (
            f"{ctx.prefix}_sincosf" if ctx.internal == "float" else f"{ctx.prefix}_sincos")
        self.lines += [f"{self.ltype} trig_sin[{len(angles)}], trig_cos[{len(angles)}];",
                       "{",
                       f"    const {self.ltype} trig_angle[{len(angles)}] = "
                       f"{{{', '.join(self.printer.doprint(a) for a in angles)}}};",
                       f"    {helper}({len(angles)}, trig_angle, trig_sin, trig_cos);",
                       "}"]

    def _pivot_checks(self) -> dict[int, list[str]]:
        """Forward dynamics checks each pivot as soon as it is computed, before anything divides
        by it: a singular D returns 1 without a division by zero (lanes: all in one mask).
        Returns the tests by the index of the statement after which they go."""
        self.check_symbols: dict[int, set] = {}  # symbols the checks after each statement read
        if not self.plan.checked:
            return {}
        out: dict[int, list[tuple[str, int]]] = {}
        checks = self.reduced.checks
        codes = self.plan.pivot_codes or [1] * (len(checks) // 2)
        for d, m, code in zip(checks[0::2], checks[1::2], codes):
            if not sp.sympify(d).free_symbols and not sp.sympify(m).free_symbols and \
                    float(d) > (0.0 if sp.sympify(d - m) == 0 else self.ctx.rtol * float(m)):
                continue  # a constant pivot that passes: no test that is always false (clang's -Wunreachable-code)
            macro = (f"{self.ctx.prefix.upper()}_{'CONTACT' if self._contact_function else 'TASK'}"
                     "_RTOL" if code == TASK_SINGULAR else pivot_rtol_macro(self.ctx.prefix))
            rtol = f"({self.ctx.internal}){macro}"  # (whatever type the user's macro has)
            at = max(_position_of(d, self.position), _position_of(m, self.position))
            self.check_symbols.setdefault(at, set()).update(sp.sympify(d).free_symbols | sp.sympify(m).free_symbols)
            pd = self.printer.doprint(d)
            if sp.sympify(d - m) == 0:
                test = f"({pd} > 0.0)" if self.vector else f"!({pd} > 0)"
            else:
                test = f"({pd} > {rtol}*({self.printer.doprint(m)}))"
                test = test if self.vector else "!" + test
            out.setdefault(at, []).append((test, code))
        return out

    def _emit_checks(self, checks, at) -> None:
        if at not in checks:
            return
        if self.vector:
            self.lines.append("all_ok &= " + "\n        & ".join(test for test, _ in checks[at]) + ";")
            return
        for code in sorted({code for _, code in checks[at]}):
            self.lines += ["if (" + "\n        || ".join(test for test, c in checks[at] if c == code) + ") {",
                           f"    return {status_macros(self.ctx.prefix)[self._status_name(code)]};",
                           "}"]

    def _status_name(self, code: int) -> str:
        """The header's name of a check's status: 3 is the contact functions' CONTACT_SINGULAR,
        the task-space functions' TASK_SINGULAR."""
        if code == TASK_SINGULAR and self._contact_function:
            return "CONTACT_SINGULAR"
        return STATUS_NAMES[code]

    @property
    def _contact_function(self) -> bool:
        """Whether the function solves with the contacts' constraints (its status 3 is theirs)."""
        return bool(set(self.plan.parts) & set(CONTACT_SOLVED))

    def _placed_writes(self) -> None:
        """Where each target is written: a scratch-array entry, and (:attr:`early_outputs`) an
        output entry with its mirror, right after the last statement it reads (so that no value
        stays live until the end of the function), an output that is a number first of all,
        before the sin/cos block (TALOS's mass matrix, 760 such entries: 955 -> 838 ns, gcc -O3
        -march=native); the others are the results written at the end (:attr:`late`)."""
        self.early: dict[int, list[str]] = {}  # lines after statement k (-1: before the statements)
        self.early_symbols: dict[int, set] = {}
        self.numbers: list[str] = []  # output entries that are numbers
        self.late = []
        mirrors: dict[str, list[str]] = {}
        for alias, source in self.plan.aliases:
            mirrors.setdefault(source, []).append(alias)
        for target, expr in zip(self.plan.targets, self.reduced.outputs):
            if not target.local and not self.early_outputs:
                self.late.append((target, expr))
                continue
            text = self.show(expr)
            self._count(expr)
            if target.local:
                lines = [f"{target.lvalue} = {text};"]
            else:
                value = f"{self.store}({text})" if self.store else text
                lines = [f"{lvalue} = {value};" for lvalue in [target.lvalue] + mirrors.get(target.lvalue, [])]
                if not sp.sympify(expr).free_symbols:
                    self.numbers += lines
                    continue
            at = _position_of(expr, self.position)
            self.early.setdefault(at, []).extend(lines)
            self.early_symbols.setdefault(at, set()).update(sp.sympify(expr).free_symbols)

    def _statements(self, checks) -> list:
        """The statements, each pivot check and each early write (:meth:`_placed_writes`) right
        after the last statement it reads; returns the results written at the end, ``(target,
        expression)``."""
        early, late = self.early, self.late
        self._emit_checks(checks, -1)
        self.lines.extend(early.get(-1, ()))
        names = self.ctx.names
        self.segments = []  # per statement: (first line, symbols its lines read)
        for k, (sym, rhs) in enumerate(self.reduced.statements):
            self.segments.append((len(self.lines), set(rhs.free_symbols) | self.early_symbols.get(k, set())
                                  | self.check_symbols.get(k, set())))
            kind = "int" if isinstance(rhs, sp.core.relational.Relational) else self.ltype  # (a branch's condition)
            self.lines.append(f"const {kind} {names[sym]} = {self.show(rhs)};")
            self.ops += count_operations(rhs)
            self.used |= rhs.free_symbols
            self._emit_checks(checks, k)
            self.lines.extend(early.get(k, ()))
        return late

    def _checked_results(self, late) -> None:
        """A checked function's results (forward dynamics, task space): every one finite (else
        status 2), then written to their output entries."""
        self.used |= set().union(*(sp.sympify(e).free_symbols for e in self.reduced.checks))
        limit, fabs = _limit(self.ctx.internal, self.ctx.scalar)
        names = self.ctx.names
        results = []
        for target, expr in late:
            if isinstance(expr, sp.Symbol) and expr in names:
                results.append(names[expr])
            else:
                self.lines.append(f"const {self.ltype} {target.lvalue} = {self.show(expr)};")
                results.append(target.lvalue)
            self._count(expr)
        writes = [(final, result) for (target, _), result in zip(late, results) for final in target.finals]
        if not results:  # a stage that only fills scratch arrays (symdyn.emit.cgen's staged functions)
            self.lines.append("return 0;")
            return
        if self.vector:
            self.lines.append("all_ok &= " + "\n        & ".join(f"({r} <= {limit}) & ({r} >= -{limit})" for r in results) + ";")
            self.lines += [f"{final} = {result};" for final, result in writes]
            self.lines.append("*ok = all_ok;")
        else:
            self.lines += ["if (" + "\n        || ".join(f"!({fabs}({r}) <= {limit})" for r in results) + ") {",
                           f"    return {status_macros(self.ctx.prefix)['NOT_FINITE']};",
                           "}"]
            self.lines += [f"{final} = {self.store}{result};" for final, result in writes]
            self.lines.append("return 0;")

    def _loops(self) -> None:
        plan, ctx = self.plan, self.ctx
        if plan.tangents:
            self.lines += self.tangent_lines
        if plan.gram:
            out, size = plan.gram
            self.lines += gram_loop(out, size, self.ltype, 4 if ctx.internal == "float" else 8, ctx.prefix, self.vector)
            self.ops += gram_ops(size)
        if plan.coriolis:
            out, n = plan.coriolis
            self.lines += coriolis_loop(out, n, self.ltype, self.store, ctx.prefix, self.vector)
            self.ops += coriolis_ops(n)
        if plan.products:
            lines, ops = product_loop(plan.products, self.store, ctx.internal, ctx.scalar, self._loop_fma(), ctx.prefix)
            self.lines += lines
            self.ops += ops
        if plan.contact_products:
            lines, ops = contact_product_loop(plan.contact_products, self.store, ctx.internal, ctx.scalar,
                                              self._loop_fma(), ctx.prefix)
            self.lines += lines
            self.ops += ops
        if plan.looped:
            solve, solve_ops = looped_solve(ctx.n, self.ltype, f"({ctx.internal}){pivot_rtol_macro(ctx.prefix)}",
                                            self.printer.literal(1.0), self.vector, plan.out_name, self.store,
                                            ctx.internal, ctx.scalar, ctx.prefix)
            self.lines += solve
            self.ops += solve_ops
        if plan.sweeps:
            lines, loop_ops = articulated_body_loops(plan.sweeps, self.printer, self.ltype, plan.out_name, self.store,
                                                     ctx.internal, ctx.scalar, ctx.prefix, self._loop_fma())
            self.lines += lines
            self.ops += loop_ops


#: an output of more entries that are numbers than this (TIAGo dual's mass matrix: 8700 of its
#: 11449 entries are 0, its branches being independent) writes each value shared by many entries
#: by a loop over a table of their indices, not one statement each: gcc -O2 took 600 MB on the
#: 8700 stores in one block (its block vectorizer compares every pair of memory accesses)
NUMBER_TABLE_FROM = 2000
#: the fewest entries of one value written by a table (:func:`number_writes`)
NUMBER_TABLE_MIN = 64


@contextlib.contextmanager
def small_pieces():
    """Within it, every size limit of the C's shape lowered so that a small robot's code takes
    every form a big one's does: bodies over 50 statements in parts of 37 lines, tables from 3
    entries of a value shared by 2, results written early (the fuzzer crosses its random robots
    with these forms; the arithmetic is the same, tests/emit/test_split_bodies.py)."""
    names = ("SPLIT_FROM_STATEMENTS", "PART_LINES", "NUMBER_TABLE_FROM", "NUMBER_TABLE_MIN", "EARLY_OUTPUTS_FROM")
    saved = {name: globals()[name] for name in names}
    globals().update(SPLIT_FROM_STATEMENTS=50, PART_LINES=37, NUMBER_TABLE_FROM=3, NUMBER_TABLE_MIN=2,
                     EARLY_OUTPUTS_FROM=-1)
    try:
        yield
    finally:
        globals().update(saved)


def number_writes(lines: list[str], name: str, vector: bool = False) -> list[str]:
    """``lines`` (``ARRAY[INDEX] = VALUE;``, an output's entries that are numbers), or where they
    are more than :data:`NUMBER_TABLE_FROM`, each value of at least :data:`NUMBER_TABLE_MIN`
    entries of one array written by a loop over a static table of the indices (``name``: the C
    function's, for the tables' names) and the other lines as they are."""
    if vector or len(lines) <= NUMBER_TABLE_FROM:
        return lines
    keys = [(m.group(1), m.group(3), int(m.group(2))) if (m := re.fullmatch(r"(\w+)\[(\d+)\] = (.+);", line))
            else None for line in lines]
    groups: dict[tuple[str, str], list[int]] = {}
    for key in filter(None, keys):
        groups.setdefault(key[:2], []).append(key[2])
    tables = {key: indices for key, indices in groups.items() if len(indices) >= NUMBER_TABLE_MIN}
    out = [line for line, key in zip(lines, keys) if key is None or key[:2] not in tables]
    for k, ((array, value), indices) in enumerate(sorted(tables.items())):
        table = f"{name}_entries{k}"
        rows = [", ".join(str(i) for i in indices[j:j + 16]) for j in range(0, len(indices), 16)]
        out += [f"static const unsigned int {table}[{len(indices)}] = {{", *(f"    {row}," for row in rows), "};",
                f"for (int k = 0; k < {len(indices)}; ++k) {{", f"    {array}[{table}[k]] = {value};", "}"]
    return out


def _part_bounds(segments: list, defined_in: dict, end_line: int, size: int) -> list[int]:
    """The first statement of each part: a part ends before it would hold more than ``size``
    lines, counting its statements, the results written with them and one line per value it
    reads from an earlier part.  (gcc's basic-block vectorizer compares every pair of memory
    accesses in a function: its memory grows with their square, so the loads and stores count
    as much as the arithmetic.)"""
    bounds, cost, loaded = [0], 0, set()
    for k, (line, symbols) in enumerate(segments):
        following = segments[k + 1][0] if k + 1 < len(segments) else end_line
        earlier = {s for s in symbols if defined_in.get(s, k) < bounds[-1]} - loaded
        if cost and cost + following - line + len(earlier) > size:
            bounds.append(k)
            cost, loaded = 0, set()
            earlier = {s for s in symbols if defined_in.get(s, k) < k}
        cost += following - line + len(earlier)
        loaded |= earlier
    return bounds


def _split(writer: "BodyWriter", body: Body, late_symbols: set, size: int) -> None:
    """Turn ``body`` (a long scalar body) into a short one that calls its parts: the lines
    before the statements stay (input checks, the sin/cos block, the scratch arrays' and a
    ``carry`` array's declarations); the statements are cut into parts of about ``size`` lines
    (:func:`_part_bounds`), each part reading a value it needs from an earlier part out of
    ``carry`` just before its first use and leaving there, right after computing it, each value
    a later part needs; the last part also writes the results and runs the loops.  A checked
    function's parts return its status."""
    names, ltype = writer.ctx.names, writer.ltype
    statements, segments = writer.reduced.statements, writer.segments
    defined_in = {sym: k for k, (sym, _) in enumerate(statements)}
    bounds = _part_bounds(segments, defined_in, writer.segment_end, size)
    chunks = list(zip(bounds, bounds[1:] + [len(statements)]))
    chunk_of = lambda index: bisect.bisect_right(bounds, index) - 1  # noqa: E731
    used_by = [set() for _ in chunks]
    for index, (_, symbols) in enumerate(segments):
        used_by[chunk_of(index)] |= {s for s in symbols if s in defined_in}
    used_by[-1] |= {s for s in late_symbols if s in defined_in}
    carried = sorted({s for c, used in enumerate(used_by) for s in used if chunk_of(defined_in[s]) < c},
                     key=lambda s: defined_in[s])
    slot = {s: k for k, s in enumerate(carried)}
    lines = body.lines
    head, tail = lines[:writer.segment_start], lines[writer.segment_end:]
    checked = writer.plan.checked
    returns = "int" if checked else "void"
    # restrict: the caller's scratch arrays never overlap (gcc -O2 vectorizes loops over them only then:
    # Solo-12's forward-dynamics derivatives, a split body, 7466 -> 6142 ns)
    params = [f"{ltype} *restrict {name}" for name, _ in writer.arrays] + [f"{ltype} *restrict carry"]
    parts = []
    for c, (first, last) in enumerate(chunks):
        start = segments[first][0] if first else writer.segment_start
        stop = segments[last][0] if last < len(statements) else writer.segment_end
        part = [f"(void){name};" for name, _ in writer.arrays] + ["(void)carry;"]
        part += lines[start:segments[first][0]] if first < last else lines[start:stop]
        loaded = set()
        for k in range(first, last):  # each carried value read just before its first use, stored right after it is made
            following = segments[k + 1][0] if k + 1 < len(statements) else writer.segment_end
            fresh = sorted((x for x in segments[k][1] if x in slot and chunk_of(defined_in[x]) < c and x not in loaded),
                           key=lambda x: defined_in[x])
            loaded.update(fresh)
            part += [f"const {ltype} {names[x]} = carry[{slot[x]}];" for x in fresh]
            part += lines[segments[k][0]:following]
            if statements[k][0] in slot:
                part.append(f"carry[{slot[statements[k][0]]}] = {names[statements[k][0]]};")
        if c == len(chunks) - 1:
            fresh = sorted((x for x in late_symbols if x in slot and chunk_of(defined_in[x]) < c and x not in loaded),
                           key=lambda x: defined_in[x])
            part += [f"const {ltype} {names[x]} = carry[{slot[x]}];" for x in fresh]
            part += tail
            if checked and not part[-1].startswith("return"):
                part.append("return 0;")
        elif checked:
            part.append("return 0;")
        parts.append((returns, params, part))
    calls = []
    arguments = ", ".join([ARGUMENTS] + [name for name, _ in writer.arrays] + ["carry"])
    for c in range(len(parts)):
        call = f"{PART}{c + 1}@({arguments})"
        if not checked:
            calls.append(f"{call};")
        elif c == len(parts) - 1:
            calls.append(f"return {call};")
        else:
            calls += [f"status = {call};", "if (status != 0) {", "    return status;", "}"]
    declarations = [f"{ltype} carry[{max(1, len(carried))}];"] + (["int status;"] if checked and len(parts) > 1 else [])
    body.lines = head + declarations + calls
    body.parts = parts


def write_body(plan: FunctionPlan, reduced: ReducedPlan, context: BodyContext, vector: bool = False) -> Body:
    """Stage 3: the C body of a reduced function (``vector``: the batch form's lanes function)."""
    return BodyWriter(plan, reduced, context, vector).write()
