"""The first two stages of the C emitter: what a function writes, then its statements.

1. :func:`collect_targets`: the function's targets, each an lvalue (an output argument's entry,
   an entry of a scratch array, or a local result) and the expression it gets, with flags that
   say what kind of target it is; the mass matrix's mirrored entries and the pivot checks.
2. :func:`reduce_targets`: the program's assignments the targets need, constants folded,
   common subexpressions eliminated (SymPy's CSE, or :func:`~symdyn.emit.emission.pair_cse`
   for very long functions), statements nothing uses pruned, numeric coefficients grouped.

The third stage, laying the statements out as C, is :mod:`symdyn.emit.cbody`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from ..derive.equations import Equations
from ..model.outputs import COMBINED, FORWARD_DERIVATIVES, REGISTRY, function_inputs, returns_status
from .emission import factor_coefficients, fold_constants, fresh_symbols, pair_cse

#: functions of at least this many statements get the pair CSE (:func:`emission.pair_cse`) instead
#: of SymPy's: in practice the Coriolis matrix of chains of about 14 joints or more (16,000
#: statements at 24 joints, 64,000 at 48), where SymPy's CSE took most of the emission's time
#: and memory.  Generic 24-joint chain: emission 22.9 -> 8.6 s, 38168 -> 36175 multiplications,
#: 15.1 -> 14.0 us at gcc -O2; `symdyn generate` of every default function at 48 joints:
#: 155 -> 93 s, 817 -> 410 MB peak.  Below, SymPy's CSE, which also groups common sums, is kept.
PAIR_CSE_FROM = 10000

#: from this many joints the Coriolis matrix, when it comes from the O(n^2) recursion
#: (:attr:`Equations.coriolis_factors`), is written by a loop over the five arrays of 6-vectors
#: (:func:`symdyn.emit.cbody.coriolis_loop`) instead of n^2 straight-line dot products: the
#: code stays linear in n (see docs/benchmarks.md for where the loop starts to pay)
LOOPED_CORIOLIS_FROM_DOF = 8

#: the scratch arrays of the Coriolis loop, in the order of ``Equations.coriolis_factors``
CORIOLIS_ARRAYS = ("cor_s", "cor_ds", "cor_f", "cor_g", "cor_e")


@dataclass(frozen=True)
class Target:
    """One value a function stores: ``lvalue`` (C) gets ``expr``.  ``local``: an entry of a
    scratch array of the body (the mass matrix's factors, forward dynamics' system), stored as
    soon as its operands are computed; otherwise a result, written at the end or, in a function
    with many results, as soon as computed (:func:`symdyn.emit.cbody.writes_results_early`)."""

    lvalue: str
    expr: sp.Expr
    local: bool = False
    #: where a checked function writes the value once every check has passed (the output
    #: entries; two for an off-diagonal entry of a symmetric output)
    finals: tuple[str, ...] = ()


@dataclass
class FunctionPlan:
    """Stage 1: what one C function computes and writes.

    ``gram``: ``(array, n)`` when the body ends with the loop filling the mass matrix's
    off-diagonal entries from the factors; ``coriolis``: ``(array, n)`` when it ends with the
    loop writing the Coriolis matrix from its factors; ``aliases``: ``(lvalue, source)`` copies written last
    (the lower triangle of a symmetric output); ``pivots``: the ``(d_j, M_jj)`` pairs checked in
    the unrolled forward dynamics, flattened; ``looped``: forward dynamics solved by a loop;
    ``sweeps``: forward dynamics by the articulated-body algorithm's loops."""

    name: str
    parts: tuple[str, ...]
    inputs: tuple[str, ...]
    out_name: str
    targets: list[Target] = field(default_factory=list)
    aliases: list[tuple[str, str]] = field(default_factory=list)
    gram: tuple[str, int] | None = None
    coriolis: tuple[str, int] | None = None
    empty_outputs: list[str] = field(default_factory=list)
    checked: bool = False
    looped: bool = False
    #: forward dynamics by the articulated-body algorithm's loops over the joints
    #: (:class:`~symdyn.derive.articulated_loops.ArticulatedLoops`, or None): the statements
    #: only fill ``fd_c``, ``fd_s`` and ``fd_t``
    sweeps: object = None
    pivots: list[sp.Expr] = field(default_factory=list)
    #: the status each pivot pair returns when its check fails (empty: 1 for every pair) and
    #: whether it is checked against the header's task tolerance macro instead of the literal one
    pivot_codes: list[int] = field(default_factory=list)
    #: a forward-dynamics derivative written as ``-Minv dtau/dx`` after the statements
    #: (:attr:`Equations.inverse_products`): ``(n, blocks, minv, stride, columns)``, ``blocks`` the
    #: ``(scratch array, output argument)`` of each derivative, ``minv`` the output argument M^-1
    #: is copied to (or None), ``stride`` the entries of one row of the scratch arrays
    #: (:func:`product_stride`), ``columns`` the product by columns' nonzero rows of dtau/dx
    #: (:func:`product_columns`) or None for the product by rows; None otherwise
    products: tuple | None = None
    #: the contact derivatives written as ``-W dF`` after the statements
    #: (:attr:`Equations.contact_products`, :class:`ContactProducts`), or None
    contact_products: "ContactProducts | None" = None
    #: derivatives written as vector tangents by loops (:class:`TangentPlan`), or None
    tangents: "TangentPlan | None" = None
    #: program symbols the function takes as given (its statements stop there: a stage of a
    #: staged function reads them from an array, see symdyn.emit.cgen)
    leaves: frozenset = frozenset()


def tangent_width(directions: int) -> int:
    """The entries of one tangent vector: the directions rounded up to a multiple of 4 (whole
    AVX vectors of doubles; the padding lanes stay zero)."""
    return -(-directions // 4) * 4


@dataclass(frozen=True)
class TangentPlan:
    """Derivatives a function writes as loops over vector tangents (:attr:`Equations.tangent_loops`):
    the steps of ``groups`` of ``tangents``, the rows of group ``groups[k]`` written to
    ``destinations[k]``, row i at ``i * strides[k]`` (an output argument, row-major n x n:
    stride n; or a scratch array whose rows keep the tangent's padding lanes: stride
    :func:`tangent_width`);
    ``coefficients`` maps each coefficient the loops read that is not a number to ``(index,
    sign)``: its value is ``sign * dv_p[index]``, ``dv_p[index]`` a plan target stored before the
    loops run (``-c`` and ``c`` share one entry)."""

    tangents: object
    groups: tuple[int, ...]
    destinations: tuple[str, ...]
    coefficients: dict  # expression -> (index in dv_p, sign)
    strides: tuple[int, ...]

    @property
    def entries(self) -> int:
        """The entries of ``dv_p``."""
        return len({index for index, _ in self.coefficients.values()})


def tangent_plan(eqs: Equations, parts, destinations, stride: int | None = None) -> tuple[list[Target], TangentPlan] | None:
    """The targets (``dv_p``: every coefficient the loops read that is not a number, each once,
    a negative one stored as its opposite) and the :class:`TangentPlan` of the derivative
    outputs ``parts`` (with ``destinations[k]`` for ``parts[k]``, rows of ``stride`` entries:
    n, the outputs' own, by default), when every one of them has vector tangents in the same
    :attr:`Equations.tangent_loops` entry; else None."""
    found = [eqs.tangents_for(part) for part in parts]
    if not found or any(f is None for f in found) or len({id(f[0]) for f in found}) != 1:
        return None
    tangents = found[0][0]
    groups = tuple(group for _, group in found)
    coefficients: dict = {}
    targets: list[Target] = []
    stored: dict = {}
    for value in tangents.coefficients(groups):
        if value.is_number:
            continue
        sign, core = (-1, -value) if _negative(value) else (1, value)
        if core not in stored:
            stored[core] = len(stored)
            targets.append(Target(f"dv_p[{stored[core]}]", core, True))
        coefficients[value] = (stored[core], sign)
    return targets, TangentPlan(tangents, groups, tuple(destinations), coefficients, (stride or eqs.n,) * len(groups))


def _negative(value: sp.Expr) -> bool:
    """Whether a coefficient is stored as its opposite: SymPy's canonical sign test, taken on
    the expression with its constants folded (unfolded, SymPy sorts terms such as
    ``cos(1.5707963267948966)*...`` by evaluating them, minutes on a 7-joint tree's derivatives)."""
    return fold_constants(value).could_extract_minus_sign()


@dataclass
class ReducedPlan:
    """Stage 2: the statements ``(symbol, expression)`` in order, the expression of each target
    (in the order of the plan's targets) and of each pivot check."""

    statements: list[tuple[sp.Symbol, sp.Expr]]
    outputs: list[sp.Expr]
    checks: list[sp.Expr]


def _factor_targets(motions, momenta, size: int) -> list[Target]:
    """The scratch entries of the mass matrix's factors: ``mass_s`` (component k of S_i at
    ``k * (size - 1) + i``) and ``mass_f`` (F_j's 6 components at ``6 j``)."""
    return ([Target(f"mass_s[{k * (size - 1) + i}]", e, True) for i, row in enumerate(motions) for k, e in enumerate(row)]
            + [Target(f"mass_f[{6 * j + k}]", e, True) for j, row in enumerate(momenta) for k, e in enumerate(row)])


def _output_targets(eqs: Equations, plan: FunctionPlan, part: str) -> None:
    """Add the entries of output ``part`` (each of its arguments, row-major) to ``plan``."""
    output = REGISTRY[part]
    matrix = eqs.output(part)
    dims = eqs.dimensions
    if output.shape(dims) != matrix.shape:
        raise AssertionError(f"{part}: derived {matrix.shape}, registered {output.shape(dims)}")
    factored = part == "mass_matrix" and bool(eqs.mass_factors)
    if part == "coriolis_matrix" and eqs.coriolis_factors and eqs.n >= LOOPED_CORIOLIS_FROM_DOF:
        n = eqs.n  # component c of vector k of each factor at array[c * n + k]
        plan.targets.extend(Target(f"{array}[{c * n + k}]", e, True)
                            for array, vectors in zip(CORIOLIS_ARRAYS, eqs.coriolis_factors)
                            for k, vector in enumerate(vectors) for c, e in enumerate(vector))
        plan.coriolis = (output.arguments[0].name, n)
        return
    for argument, (rows, cols) in output.argument_shapes(dims):
        block = matrix[:, argument.first:argument.first + cols]
        arg = argument.name
        if cols == 0:
            plan.empty_outputs.append(arg)
        for i in range(rows):
            for j in range(cols):
                if output.symmetric and j < i:
                    if not factored:  # the loop writes both triangles
                        plan.aliases.append((f"{arg}[{i * cols + j}]", f"{arg}[{j * cols + i}]"))
                elif not (factored and j > i):
                    plan.targets.append(Target(f"{arg}[{i * cols + j}]", block[i, j]))
        if factored:  # D[i][j] = S_i . F_j (i < j) as a loop over two arrays of 6-vectors
            plan.targets.extend(_factor_targets(*eqs.mass_factors, rows))
            plan.gram = (arg, rows)


def _checked_targets(eqs: Equations, plan: FunctionPlan) -> None:
    """A function that returns a status (task space, the inverse mass matrix, the
    forward-dynamics derivatives): every result to a local first (``result0``, ...), written to
    its output entries only when every pivot check has passed; the checks of its factorizations."""
    dims = eqs.dimensions
    k = 0
    for part in plan.parts:
        output = REGISTRY[part]
        matrix = eqs.output(part)
        for argument, (rows, cols) in output.argument_shapes(dims):
            arg = argument.name
            for i in range(rows):
                for j in range(cols):
                    if output.symmetric and j < i:
                        continue  # written with its mirror above the diagonal
                    finals = (f"{arg}[{i * cols + j}]",) + ((f"{arg}[{j * cols + i}]",) if output.symmetric and j > i else ())
                    plan.targets.append(Target(f"result{k}", matrix[i, j], finals=finals))
                    k += 1
    _set_checks(eqs, plan)


def _set_checks(eqs: Equations, plan: FunctionPlan) -> None:
    """The pivot checks of a status-returning function (:meth:`Equations.checks_for` its parts)."""
    checks = eqs.checks_for(plan.parts)
    plan.pivots = [e for pivot, diagonal, _ in checks for e in (pivot, diagonal)]
    plan.pivot_codes = [code for _, _, code in checks]


#: the scratch array of each forward-dynamics derivative's dtau/dx in the product loop
PRODUCT_ARRAYS = {"forward_dynamics_dq": "fdd_q", "forward_dynamics_dqd": "fdd_v"}


def product_targets(eqs: Equations, parts) -> tuple[list[Target], TangentPlan | None]:
    """The scratch entries (row-major) of the dtau/dx of each forward-dynamics derivative among
    ``parts`` (:attr:`Equations.inverse_products`), stored as soon as computed; or, where they
    have vector tangents, the coefficients those read and their :class:`TangentPlan`."""
    wanted = [part for part in FORWARD_DERIVATIVES if part in parts]
    looped = tangent_plan(eqs, wanted, [PRODUCT_ARRAYS[part] for part in wanted], product_stride(eqs))
    if looped is not None:
        return looped
    return _written_products(eqs, parts), None


def product_stride(eqs: Equations) -> int:
    """The entries of one row of the product scratch arrays: n rounded up as the tangents' width
    (whole vectors; the padding lanes zero), for the products' loops over whole rows (puma560
    and ur5's rows of 6 entries unpadded: ur5's forward-dynamics derivatives 663 -> 804 ns at
    gcc -O3 -march=native)."""
    return tangent_width(eqs.n)


#: the product ``-Minv dtau/dx`` of a straight-line dtau/dx is written by columns, each column
#: of the result the sum over the nonzero entries of dtau/dx's column only, where those skip at
#: least this share of all the terms (a floating base's legs: a leg's joint moves the base and
#: its own leg only, the base's position moves nothing; Solo-12 skips 42%)
COLUMN_PRODUCT_SAVING = 0.25


def product_columns(eqs: Equations, parts) -> tuple | None:
    """For each forward-dynamics derivative among ``parts`` (in order), per column j the rows k
    of its dtau/dx not identically zero; None where the saving is under
    :data:`COLUMN_PRODUCT_SAVING` or dtau/dx has vector tangents (then the product goes by rows)."""
    wanted = [part for part in FORWARD_DERIVATIVES if part in parts]
    if any(eqs.tangents_for(part) is not None for part in wanted):
        return None
    _, dq, dqd, _ = eqs.inverse_products
    matrices = dict(zip(FORWARD_DERIVATIVES, (dq, dqd)))
    n = eqs.n
    columns = tuple(tuple(tuple(k for k in range(n) if matrices[part][k, j] != 0) for j in range(n))
                    for part in parts if part in matrices)
    kept = sum(len(rows) for block in columns for rows in block)
    return columns if kept <= (1 - COLUMN_PRODUCT_SAVING) * len(columns) * n * n else None


def _written_products(eqs: Equations, parts) -> list[Target]:
    """Each dtau/dx entry into its scratch array, rows of :func:`product_stride` entries, the
    padding lanes zero; for a product by columns (:func:`product_columns`) the entries it reads
    only."""
    _, dq, dqd, _ = eqs.inverse_products
    matrices = dict(zip(FORWARD_DERIVATIVES, (dq, dqd)))
    n, stride = eqs.n, product_stride(eqs)
    if product_columns(eqs, parts) is not None:
        return [Target(f"{PRODUCT_ARRAYS[part]}[{i * stride + j}]", matrices[part][i, j], True)
                for part in parts if part in matrices for i in range(n) for j in range(n) if matrices[part][i, j] != 0]
    return [Target(f"{PRODUCT_ARRAYS[part]}[{i * stride + j}]", matrices[part][i, j] if j < n else sp.S.Zero, True)
            for part in parts if part in matrices for i in range(n) for j in range(stride)]


def minv_targets(eqs: Equations) -> list[Target]:
    """M^-1 into the scratch array ``fdd_m`` (row-major), stored as soon as computed."""
    Minv, n = eqs.inverse_products[0], eqs.n
    return [Target(f"fdd_m[{i * n + j}]", Minv[i, j], True) for i in range(n) for j in range(n)]


def _product_targets(eqs: Equations, plan: FunctionPlan) -> None:
    """A function with a forward-dynamics derivative: M^-1 and each dtau/dx into scratch arrays
    (``fdd_m``, ``fdd_q``, ``fdd_v``, row-major) as soon as computed; the loop that ends the body
    forms ``-Minv dtau/dx``, checks every result and writes the outputs."""
    blocks = [(PRODUCT_ARRAYS[part], REGISTRY[part].arguments[0].name) for part in plan.parts if part in PRODUCT_ARRAYS]
    targets, plan.tangents = product_targets(eqs, plan.parts)
    plan.targets = minv_targets(eqs) + targets
    minv = REGISTRY["mass_matrix_inverse"].arguments[0].name if "mass_matrix_inverse" in plan.parts else None
    plan.products = (eqs.n, tuple(blocks), minv, product_stride(eqs), product_columns(eqs, plan.parts))
    _set_checks(eqs, plan)


#: where each contact output's entries come from in the contact product loop: ``(block, first
#: row)`` of the results ``cdd_r`` (block 0 by q, 1 by qd), or ``(source array, first row)`` of
#: the solution ``cdd_a`` and of W's first n columns ``cdd_w`` (dqdd/dtau = K, dlambda/dtau = -S^T)
CONTACT_PRODUCT_SOURCES = {
    "contact_accelerations": ("cdd_a", 0), "contact_forces": ("cdd_a", 1),
    "contact_accelerations_dq": (0, 0), "contact_forces_dq": (0, 1),
    "contact_accelerations_dqd": (1, 0), "contact_forces_dqd": (1, 1),
    "contact_accelerations_dtau": ("cdd_w", 0), "contact_forces_dtau": ("cdd_w", 1),
}
#: the scratch array of each block of residual derivatives (by q, by qd) in the product loop
CONTACT_PRODUCT_ARRAYS = ("cdd_q", "cdd_v")


@dataclass(frozen=True)
class ContactProducts:
    """The contact derivatives' product loops (:attr:`Equations.contact_products`): ``n`` joints'
    velocities, ``m`` constraint rows, ``rows`` = n + m (accelerations then forces), ``stride``
    the rows rounded up to whole vectors (:func:`tangent_width`: every column below is that long,
    column-major, the padding zero).  W's columns are formed first, ``W[:, c] = M^-1[:, c] (c < n)
    + sum_l U[:, l] V[c, l]`` (``cdd_m``, ``cdd_u``, the entries of V in ``cdd_t``), ``forming[c]``
    the l where V[c, l] is not identically zero; then ``blocks``, per block of residual
    derivatives computed (by q, by qd), ``(block, array, columns)``, ``columns[j]`` the rows k
    where dF's column j is not identically zero; ``writes``: ``(output argument, source, first
    row, rows, columns)``, the output's entry (i, j) read from ``source[j * stride + first + i]``."""

    n: int
    m: int
    rows: int
    stride: int
    forming: tuple
    blocks: tuple
    writes: tuple


def _contact_product_plan(eqs: Equations, plan: FunctionPlan) -> None:
    """A function with contact derivatives by q or qd (and only contact outputs): M^-1 and U
    (column-major, ``cdd_m``, ``cdd_u``), V's nonzero entries (``cdd_t``), the solution
    (``cdd_a``) and the nonzero entries of each needed dF (``cdd_q``, ``cdd_v``, row-major n
    columns) into scratch arrays as soon as computed; the loops that end the body form W, then
    ``-W dF`` column by column, check every result and write the outputs."""
    Minv, U, V, dF_q, dF_qd, solution = eqs.contact_products
    n, (rows, m) = eqs.n, U.shape
    stride = tangent_width(rows)
    wanted = sorted({CONTACT_PRODUCT_SOURCES[part][0] for part in plan.parts} & {0, 1})
    blocks = tuple((block, CONTACT_PRODUCT_ARRAYS[block],
                    tuple(tuple(k for k in range(rows) if (dF_q, dF_qd)[block][k, j] != 0) for j in range(n)))
                   for block in wanted)
    forming = tuple(tuple(l for l in range(m) if V[c, l] != 0) for c in range(rows))
    targets = [Target(f"cdd_m[{c * stride + i}]", Minv[i, c] if i < n else sp.S.Zero, True)
               for c in range(n) for i in range(stride)]
    targets += [Target(f"cdd_u[{l * stride + i}]", U[i, l] if i < rows else sp.S.Zero, True)
                for l in range(m) for i in range(stride)]
    targets += [Target(f"cdd_t[{c * m + l}]", V[c, l], True) for c in range(rows) for l in forming[c]]
    targets += [Target(f"cdd_a[{i}]", solution[i], True) for i in range(rows)]
    for block, array, columns in blocks:
        dF = (dF_q, dF_qd)[block]
        targets += [Target(f"{array}[{k * n + j}]", dF[k, j], True) for j, nonzero in enumerate(columns) for k in nonzero]
    writes = []
    for part in plan.parts:
        source, half = CONTACT_PRODUCT_SOURCES[part]
        first, count = (0, n) if half == 0 else (n, rows - n)
        columns = 1 if source == "cdd_a" else n
        if isinstance(source, int):
            source = f"cdd_r + {wanted.index(source) * n * stride}"
        writes.append((REGISTRY[part].arguments[0].name, source, first, count, columns))
    plan.targets = targets
    plan.contact_products = ContactProducts(n, m, rows, stride, forming, blocks, tuple(writes))
    _set_checks(eqs, plan)


def collect_targets(eqs: Equations, name: str) -> FunctionPlan:
    """Stage 1 for the function ``name`` (an output, or a combined function of several)."""
    parts = COMBINED.get(name, (name,))
    plan = FunctionPlan(name, parts, function_inputs(name), REGISTRY[parts[0]].arguments[0].name)
    if returns_status(name) and eqs.checks_for(parts):
        plan.checked = True
        if eqs.inverse_products and set(parts) & set(PRODUCT_ARRAYS):
            _product_targets(eqs, plan)
        elif (eqs.contact_products and set(parts) <= set(CONTACT_PRODUCT_SOURCES)
              and any(isinstance(CONTACT_PRODUCT_SOURCES[part][0], int) for part in parts)):
            _contact_product_plan(eqs, plan)
        else:
            _checked_targets(eqs, plan)
        return plan
    plan.checked = name == "forward_dynamics" and bool(eqs.pivots)
    plan.looped = plan.checked and bool(eqs.fd_system)
    plan.sweeps = eqs.articulated_loops if plan.checked else None
    n = eqs.n
    if plan.sweeps:  # each joint's cos and sin and its force less friction, for the loops
        loops = plan.sweeps
        for j, (c, s) in enumerate(loops.angles):
            plan.targets += [Target(f"fd_c[{j}]", c, True), Target(f"fd_s[{j}]", s, True)]
        plan.targets += [Target(f"fd_t[{j}]", e, True) for j, e in enumerate(loops.tau_effective)]
    elif plan.looped:  # M's lower triangle (or the factor arrays) and rhs into local arrays
        system, rhs, factors = eqs.fd_system
        plan.targets = [Target(f"fd_M[{j * n + i}]", system[i, j], True) for i in range(n) for j in range(i, n)
                        if j == i or not factors]  # the factor loop writes both triangles
        if factors:
            plan.targets += _factor_targets(*factors, n)
            plan.gram = ("fd_M", n)
        plan.targets += [Target(f"fd_b[{i}]", rhs[i], True) for i in range(n)]
    elif plan.checked:  # results go to locals first: qdd is written only when every check passes
        matrix = eqs.output(name)
        plan.targets = [Target(f"result{i}", matrix[i], finals=(f"{plan.out_name}[{i}]",)) for i in range(n)]
        plan.pivots = [e for pair in eqs.pivots for e in pair]
    else:
        looped = tangent_plan(eqs, parts, [REGISTRY[part].arguments[0].name for part in parts])
        if looped is not None:
            plan.targets, plan.tangents = looped
            return plan
        for part in parts:
            _output_targets(eqs, plan, part)
    return plan


def _prune(statements, results):
    """Drop the statements nothing uses any more: folding constants can cancel a term (a
    coefficient that folds to exactly 0), leaving its intermediate unused."""
    live = set().union(*(sp.sympify(e).free_symbols for e in results)) if results else set()
    kept = []
    for sym, rhs in reversed(statements):
        if sym in live:
            kept.append((sym, rhs))
            live |= rhs.free_symbols
    return kept[::-1]


def merge_cse(program_assigns, replacements):
    """Interleave CSE replacements with program assignments so each follows its dependencies."""
    index = {sym: k for k, (sym, _) in enumerate(program_assigns)}
    slot: dict[sp.Symbol, int] = {}
    buckets: dict[int, list] = {}
    for sym, rhs in replacements:
        deps = [index.get(s, slot.get(s, -1)) for s in rhs.free_symbols]
        position = max(deps, default=-1)
        slot[sym] = position
        buckets.setdefault(position, []).append((sym, rhs))
    merged = list(buckets.get(-1, []))
    for k, item in enumerate(program_assigns):
        merged.append(item)
        merged.extend(buckets.get(k, []))
    return merged


def reduce_targets(eqs: Equations, plan: FunctionPlan) -> ReducedPlan:
    """Stage 2: fold, eliminate common subexpressions, prune, group coefficients."""
    assigns = list(eqs.program.needed_for([t.expr for t in plan.targets] + plan.pivots, plan.leaves))
    folded = [(s, fold_constants(r)) for s, r in assigns]
    outputs = [fold_constants(sp.sympify(t.expr)) for t in plan.targets]
    checks = [fold_constants(sp.sympify(e)) for e in plan.pivots]
    cse_symbols = fresh_symbols("cse", [r for _, r in folded] + outputs + checks + [s for s, _ in folded])
    if len(folded) >= PAIR_CSE_FROM:
        replacements, reduced = pair_cse([r for _, r in folded] + outputs + checks, cse_symbols)
    else:
        replacements, reduced = sp.cse([r for _, r in folded] + outputs + checks, symbols=cse_symbols, order="none")
    program = [(s, r) for (s, _), r in zip(folded, reduced[:len(folded)])]
    final_outputs = reduced[len(folded):len(folded) + len(outputs)]
    final_checks = list(reduced[len(folded) + len(outputs):])
    statements = _prune(merge_cse(program, replacements), list(final_outputs) + final_checks)
    # terms sharing a numeric coefficient grouped (printing and counting only: unevaluated)
    statements = [(sym, factor_coefficients(rhs)) for sym, rhs in statements]
    final_outputs = [factor_coefficients(sp.sympify(e)) for e in final_outputs]
    return ReducedPlan(statements, final_outputs, final_checks)
