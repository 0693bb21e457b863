"""C99 emitter: lays the derived equations out as straight-line C through Jinja2 templates.

This module derives nothing: it takes an :class:`~symdyn.derive.equations.Equations`, keeps the
intermediate assignments each function needs (dead code removed), eliminates further common
subexpressions, folds constants, prints with :mod:`symdyn.emit.cprinter` and renders the templates in
``templates/`` (shipped in the wheel as ``symdyn.templates``).
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field

import sympy as sp

from .._version import __version__
from ..model.errors import warn
from .cprinter import CPrinter, VectorUnsupported, count_operations
from .emission import comment_text, factor_coefficients, fold_constants, pair_cse, source_label, template_environment
from ..derive.equations import Equations
from ..model.tolerances import pivot_rtol
from ..model.outputs import ALL_OUTPUTS, COMBINED, COMBINED_SPECS, REGISTRY, Dimensions

ARG_DOCS = {
    "q": "joint positions, N (rad for revolute, m for prismatic joints)",
    "qd": "joint velocities, N (rad/s or m/s)",
    "qdd": "joint accelerations, N (rad/s^2 or m/s^2)",
    "tau": "joint torques/forces, N (N m or N)",
    "p": "runtime parameters, NP, in the order listed above",
}

#: functions of at least this many statements get the pair CSE (:func:`emission.pair_cse`) instead
#: of SymPy's: in practice the Coriolis matrix of chains of about 14 joints or more (16,000
#: statements at 24 joints, 64,000 at 48), where SymPy's CSE took most of the emission's time
#: and memory.  Generic 24-joint chain: emission 22.9 -> 8.6 s, 38168 -> 36175 multiplications,
#: 15.1 -> 14.0 us at gcc -O2; `symdyn generate` of every default function at 48 joints:
#: 155 -> 93 s, 817 -> 410 MB peak.  Below, SymPy's CSE, which also groups common sums, is kept.
PAIR_CSE_FROM = 10000

#: scratch arrays of the function body (not the caller's outputs)
LOCAL_ARRAYS = ("mass_s[", "mass_f[", "fd_M[", "fd_b[")

#: precisions of the generated C: double, float (float all the way: no double operation, for
#: single-precision FPUs), mixed (float arguments, forward dynamics computed in double inside)
PRECISION_CHOICES = ("double", "float", "mixed")


def scalar_type(precision: str) -> str:
    """The C type of the arguments for a precision."""
    if precision not in PRECISION_CHOICES:
        raise ValueError(f"precision must be one of {', '.join(PRECISION_CHOICES)}, not {precision!r}")
    return "double" if precision == "double" else "float"


_COMBINED_SUMMARIES = {c.name: c.summary for c in COMBINED_SPECS}


def _dimensions(eqs: Equations) -> Dimensions:
    """The sizes the outputs of ``eqs`` depend on."""
    return Dimensions(eqs.n, len(eqs.robot.actuated_joints), len(eqs.base_parameters))


@dataclass
class CFunction:
    name: str
    summary: str
    args: list[tuple[str, str, str, bool]]  # (c type, name, doc, is_output)
    lines: list[str]
    ops: Counter = field(default_factory=Counter)
    unused: list[str] = field(default_factory=list)
    returns: str = "void"
    returns_doc: str = ""
    #: measured code size and stack use on the size-report target (see generate_c), or ""
    size_text: str = ""
    #: type of the sin/cos block at the top ("double", "float") or "" when there is none
    trig_type: str = ""
    #: the batch form (see build_function), or None
    batch: dict | None = None
    #: whether the body has the mass matrix's off-diagonal loop (see _gram_loop)
    gram_loop: bool = False

    @property
    def batch_args(self) -> str:
        """The batch function's parameters: count, then the scalar function's arrays."""
        return ", ".join(["int count"] + [f"{ctype}{name}" for ctype, name, _, _ in self.args])

    @property
    def signature_args(self) -> str:
        return ", ".join(f"{ctype}{name}" for ctype, name, _, _ in self.args)

    @property
    def ops_text(self) -> str:
        o = self.ops

        def count(k, one, many):
            return f"{k} {one if k == 1 else many}"
        text = (f"{count(o['mul'], 'multiplication', 'multiplications')}, "
                f"{count(o['add'], 'addition/subtraction', 'additions/subtractions')}, "
                f"{count(o['div'], 'division', 'divisions')}, {o['trig']} sin/cos")
        if o["sqrt"]:
            text += f", {count(o['sqrt'], 'square root', 'square roots')}"
        if o["other"]:
            text += f", {o['other']} other (sign, pow)"
        return text


def _gram_loop(out: str, size: int, ltype: str, element_bytes: int, prefix: str, vector: bool) -> list[str]:
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
    """
    m = size - 1

    def dot(f, index="i"):
        return " + ".join(f"mass_s[{k * m} + {index}]*{f}{k}" for k in range(6))
    plain = [f"for (int j = {m}; j >= 1; --j) {{",
             f"    const {ltype} *f = mass_f + 6 * (j - 1);",
             f"    const {ltype} f0 = f[0], f1 = f[1], f2 = f[2], f3 = f[3], f4 = f[4], f5 = f[5];",
             "    for (int i = 0; i < j; ++i) {",
             f"        {out}[j * {size} + i] = {out}[i * {size} + j] = {dot('f')};",
             "    }",
             "}"]
    if vector:
        return plain
    P, vec = prefix.upper(), f"{prefix}_gram_vec"
    lanes = f"(int)(sizeof({vec}) / sizeof({ltype}))"
    base = 16 // element_bytes  # lanes of a 16-byte vector; twice as many in 32 bytes

    def strided(lane_range):
        """The entries above the diagonal (column j, rows i + lane), lane by lane: written out,
        since gcc -O2 keeps a loop over the lanes (1240 -> 1340 ns at 24 joints)."""
        return [f"            {out}[(i + {lane}) * {size} + j{minus}] = {row}[{lane}];"
                for row, minus in (("row_j", ""), ("row_g", " - 1")) for lane in lane_range]
    loads = [f"            __builtin_memcpy(&s{k}, mass_s + {k * m} + i, sizeof s{k});" for k in range(6)]
    return [f"#ifdef {P}_GRAM_BYTES",
            "{",
            f"    typedef {ltype} {vec} __attribute__((vector_size({P}_GRAM_BYTES)));",
            f"    int j = {m};",
            "    /* rows j and j - 1 together: lanes i .. i + lanes - 1 of both */",
            "    for (; j >= 2; j -= 2) {",
            f"        const {ltype} *f = mass_f + 6 * (j - 1), *g = f - 6;",
            f"        const {ltype} f0 = f[0], f1 = f[1], f2 = f[2], f3 = f[3], f4 = f[4], f5 = f[5];",
            f"        const {ltype} g0 = g[0], g1 = g[1], g2 = g[2], g3 = g[3], g4 = g[4], g5 = g[5];",
            "        int i = 0;",
            f"        for (; i + {lanes} <= j - 1; i += {lanes}) {{",
            f"            {vec} s0, s1, s2, s3, s4, s5, row_j, row_g;",
            *loads,
            f"            row_j = {' + '.join(f's{k}*f{k}' for k in range(6))};",
            f"            row_g = {' + '.join(f's{k}*g{k}' for k in range(6))};",
            f"            __builtin_memcpy({out} + j * {size} + i, &row_j, sizeof row_j);",
            f"            __builtin_memcpy({out} + (j - 1) * {size} + i, &row_g, sizeof row_g);",
            *strided(range(base)),
            f"#if {P}_GRAM_BYTES >= 32",
            *strided(range(base, 2 * base)),
            "#endif",
            "        }",
            "        for (; i < j - 1; ++i) {",
            f"            {out}[j * {size} + i] = {out}[i * {size} + j] = {dot('f')};",
            f"            {out}[(j - 1) * {size} + i] = {out}[i * {size} + j - 1] = {dot('g')};",
            "        }",
            f"        {out}[j * {size} + i] = {out}[i * {size} + j] = {dot('f')};",
            "    }",
            "    if (j == 1) {",
            f"        const {ltype} f0 = mass_f[0], f1 = mass_f[1], f2 = mass_f[2], f3 = mass_f[3], "
            "f4 = mass_f[4], f5 = mass_f[5];",
            f"        {out}[{size}] = {out}[1] = {dot('f', '0')};",
            "    }",
            "}",
            "#else",
            *plain,
            "#endif"]


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


#: the unit of each field of a link, for the header's description of parameters and constants
FIELD_UNITS = {"a": "m", "alpha": "rad", "d": "m", "theta": "rad", "mass": "kg", "com": "m",
               "inertia": "kg m^2", "armature": "kg m^2 or kg", "damping": "N m s/rad or N s/m",
               "coulomb": "N m or N", "origin": "m and rad", "limits": "rad or m, per s, N m or N"}


def _link_fields(link):
    return (("a", (link.a,)), ("alpha", (link.alpha,)), ("d", (link.d,)), ("theta", (link.theta,)),
            ("mass", (link.mass,)), ("com", link.com), ("inertia", link.inertia),
            ("armature", (link.armature,)), ("damping", (link.damping,)), ("coulomb", (link.coulomb,)),
            ("origin", link.origin.expressions() if link.origin is not None else ()))


def parameter_uses(robot, symbol) -> str:
    """Where a runtime parameter enters the model, with the fields' units: what it means."""
    uses = []
    if any(symbol in sp.sympify(g).free_symbols for g in robot.gravity):
        uses.append("gravity (m/s^2)")
    for label, placement in (("base", robot.base), ("tool", robot.tool)):
        if placement is not None and any(symbol in sp.sympify(v).free_symbols for v in placement.expressions()):
            uses.append(f"{label} placement (m and rad)")
    for k, link in enumerate(robot.links):
        fields = [f"{name} ({FIELD_UNITS[name]})" for name, values in _link_fields(link)
                  if any(symbol in sp.sympify(v).free_symbols for v in values)]
        if link.fixed is not None and any(symbol in sp.sympify(v).free_symbols for v in link.fixed):
            fields.append("placement")
        if fields:
            uses.append(f"link {k + 1} ({link.name}): " + ", ".join(fields))
    return "; ".join(uses) if uses else "unused"


def model_constants(robot) -> list[str]:
    """The numbers folded into the code, one line each: gravity and every link's mass, COM and
    inertia about the COM (entries that depend on runtime parameters are marked)."""
    def show(values):
        return ", ".join(f"{float(v):.6g}" if sp.sympify(v).is_number else "(runtime)" for v in values)
    lines = [f"gravity [{show(robot.gravity)}] m/s^2 (world frame)"]
    for label, placement, frame in (("base", robot.base, "in the world"),
                                    ("tool", robot.tool, "in the last link's frame")):
        if placement is not None:
            lines.append(f"{label} {frame}: xyz [{show(placement.xyz)}] m, rpy [{show(placement.rpy)}] rad")
    for k, link in enumerate(robot.links):
        if link.origin is not None:
            lines.append(f"joint {k + 1} ({link.name}): origin xyz [{show(link.origin.xyz)}] m, rpy "
                         f"[{show(link.origin.rpy)}] rad, axis [{show(link.axis)}]")
        lines.append(f"link {k + 1} ({link.name}): mass {show((link.mass,))} kg, com [{show(link.com)}] m, "
                     f"inertia [xx yy zz xy xz yz] [{show(link.inertia)}] kg m^2")
        if link.limits is not None:
            limits = link.limits
            parts = [f"{name} {show((value,))}" for name, value in (("lower", limits.lower), ("upper", limits.upper),
                     ("velocity", limits.velocity), ("effort", limits.effort)) if value is not None]
            lines.append(f"joint {k + 1} ({link.name}) limits (not used by these functions): {', '.join(parts)}")
    return lines


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


def _hoisted_angles(statements, results, computed) -> list[sp.Expr]:
    """The arguments of the sines and cosines that depend on the inputs only (not on a computed
    quantity), in order of first use: they are computed in one block at the top of a function."""
    angles: list[sp.Expr] = []
    seen = set()
    for expr in [rhs for _, rhs in statements] + [sp.sympify(e) for e in results]:
        for atom in sorted(expr.atoms(sp.sin, sp.cos), key=sp.default_sort_key):
            arg = atom.args[0]
            if arg not in seen and not (arg.free_symbols & computed) and arg.free_symbols:
                seen.add(arg)
                angles.append(arg)
    return angles


def build_functions(eqs: Equations, name: str, precision: str, prefix: str,
                    batch_form: bool = False) -> list[CFunction]:
    """The C functions of one output: one function, or for forward dynamics the checked
    function (``int`` status) and the plain one of the contract that calls it."""
    built = build_function(eqs, name, precision, prefix, batch_form)
    if name != "forward_dynamics" or not eqs.pivots:
        return [built]
    plain = CFunction(
        name=name, summary=built.summary + f" Same as {prefix}_{name}_checked, without the status: "
        "where that returns nonzero, qdd is left unchanged.",
        args=built.args, lines=[f"(void){prefix}_{built.name}({', '.join(a for _, a, _, _ in built.args)});"],
        ops=built.ops)
    return [built, plain]


def build_function(eqs: Equations, name: str, precision: str, prefix: str, batch_form: bool = False) -> CFunction:
    """Straight-line C body of one output function (forward dynamics: the checked function);
    with ``batch_form``, also the batch form over arrays of states (``CFunction.batch``)."""
    n = eqs.n
    real = f"{prefix}_real"
    parts = COMBINED.get(name, (name,))  # the outputs this function writes
    out_name = REGISTRY[parts[0]].arguments[0].name
    targets: list[tuple[str, sp.Expr]] = []
    aliases: list[tuple[str, str]] = []
    gram: tuple[str, int] | None = None  # (output, n) of a mass matrix written by a loop
    empty_outputs: list[str] = []  # output arguments with no entry (a reaction map with no actuated joint)
    checked = name == "forward_dynamics" and bool(eqs.pivots)
    looped = checked and bool(eqs.fd_system)  # M qdd = rhs solved by a loop (Equations.fd_system)
    if looped:  # M's upper triangle (or the factor arrays) and rhs into local arrays
        system, rhs, factors = eqs.fd_system
        targets = [(f"fd_M[{j * n + i}]", system[i, j]) for i in range(n) for j in range(i, n)
                   if j == i or not factors]  # lower triangle (the factor loop writes both)
        if factors:
            targets += [(f"mass_s[{k * (n - 1) + i}]", e) for i, row in enumerate(factors[0]) for k, e in enumerate(row)]
            targets += [(f"mass_f[{6 * j + k}]", e) for j, row in enumerate(factors[1]) for k, e in enumerate(row)]
            gram = ("fd_M", n)
        targets += [(f"fd_b[{i}]", rhs[i]) for i in range(n)]
    elif checked:  # results go to locals first: qdd is written only when every check passes
        matrix = eqs.output(name)
        targets = [(f"result{i}", matrix[i]) for i in range(n)]
    for part in (() if checked else parts):
        output = REGISTRY[part]
        matrix = eqs.output(part)
        if output.shape(_dimensions(eqs)) != matrix.shape:
            raise AssertionError(f"{part}: derived {matrix.shape}, registered {output.shape(_dimensions(eqs))}")
        symmetric = output.symmetric
        factored = symmetric and bool(eqs.mass_factors)
        for argument, (rows, cols) in output.argument_shapes(_dimensions(eqs)):
            block = matrix[:, argument.first:argument.first + cols]
            if cols == 0:
                empty_outputs.append(argument.name)
            arg = argument.name
            for i in range(rows):
                for j in range(cols):
                    if symmetric and j < i:
                        if not factored:  # the loop writes both triangles
                            aliases.append((f"{arg}[{i * cols + j}]", f"{arg}[{j * cols + i}]"))
                    elif not (factored and j > i):
                        targets.append((f"{arg}[{i * cols + j}]", block[i, j]))
            if factored:  # D[i][j] = S_i . F_j (i < j) as a loop over two arrays of 6-vectors
                motions, momenta = eqs.mass_factors
                targets += [(f"mass_s[{k * (rows - 1) + i}]", e) for i, row in enumerate(motions) for k, e in enumerate(row)]
                targets += [(f"mass_f[{6 * j + k}]", e) for j, row in enumerate(momenta) for k, e in enumerate(row)]
                gram = (arg, rows)
    checks = [e for pair in eqs.pivots for e in pair] if checked and not looped else []
    assigns = list(eqs.program.needed_for([e for _, e in targets] + checks))
    folded = [(s, fold_constants(r)) for s, r in assigns]
    outputs = [fold_constants(sp.sympify(e)) for _, e in targets]
    checks = [fold_constants(sp.sympify(e)) for e in checks]
    cse_symbols = sp.numbered_symbols("cse", real=True)
    if len(folded) >= PAIR_CSE_FROM:
        replacements, reduced = pair_cse([r for _, r in folded] + outputs + checks, cse_symbols)
    else:
        replacements, reduced = sp.cse([r for _, r in folded] + outputs + checks, symbols=cse_symbols, order="none")
    program = [(s, r) for (s, _), r in zip(folded, reduced[:len(folded)])]
    final_outputs = reduced[len(folded):len(folded) + len(outputs)]
    final_checks = reduced[len(folded) + len(outputs):]
    statements = _prune(merge_cse(program, replacements), list(final_outputs) + list(final_checks))
    # terms sharing a numeric coefficient grouped (printing and counting only: unevaluated)
    statements = [(sym, factor_coefficients(rhs)) for sym, rhs in statements]
    final_outputs = [factor_coefficients(sp.sympify(e)) for e in final_outputs]

    # precision "mixed": float arguments everywhere, but forward dynamics computed inside in
    # double (for robots whose D is too ill-conditioned for float); "float" is float all the way.
    scalar = scalar_type(precision)
    internal = "double" if (precision == "mixed" and name == "forward_dynamics") else scalar
    rtol_value = pivot_rtol(internal)  # checked in the arithmetic the pivots are computed in
    local_type = real if internal == scalar else internal
    cast = "(double)" if internal != scalar else ""
    names: dict[sp.Symbol, str] = {}
    inputs = REGISTRY[parts[0]].inputs
    for group in inputs:
        for k, sym in enumerate(getattr(eqs, group)):
            names[sym] = f"{cast}{group}[{k}]"
    for k, sym in enumerate(eqs.parameters):
        names[sym] = f"{cast}p[{k}]"
    for sym, _ in statements:
        names[sym] = sym.name.lstrip("_")
    angles = _hoisted_angles(statements, list(final_outputs) + list(final_checks), {sym for sym, _ in statements})
    trig_helper = (f"{prefix}_sincosf" if internal == "float" else f"{prefix}_sincos") if angles else ""

    def emit(vector: bool):
        """The body's lines: scalar (``vector`` False: early returns on a singular D) or the
        lanes function of the batch form (vector types; forward dynamics gathers the checks in
        the mask ``ok`` instead of returning)."""
        vreal = f"{prefix}_vreal"
        printer = CPrinter(names, internal, vector_prefix=prefix if vector else "")
        for k, arg in enumerate(angles):
            printer.trig[sp.sin(arg)] = f"trig_sin[{k}]"
            printer.trig[sp.cos(arg)] = f"trig_cos[{k}]"
        ltype = vreal if vector else local_type
        lines, ops = [], Counter()
        used = set()
        if angles:
            used |= set().union(*(a.free_symbols for a in angles))
            lines.append(f"{ltype} trig_sin[{len(angles)}], trig_cos[{len(angles)}];")
            lines.append("{")
            lines.append(f"    const {ltype} trig_angle[{len(angles)}] = {{{', '.join(printer.doprint(a) for a in angles)}}};")
            helper = f"{prefix}_vsincos" if vector else trig_helper
            lines.append(f"    {helper}({len(angles)}, trig_angle, trig_sin, trig_cos);")
            lines.append("}")

        # Forward dynamics checks each pivot as soon as it is computed, before anything divides by
        # it: a singular D returns 1 without a division by zero.  (Lanes: all checks in one mask.)
        position = {sym: k for k, (sym, _) in enumerate(statements)}
        pivot_checks: dict[int, list[str]] = {}
        if checked:
            rtol = printer.literal(rtol_value)
            for d, m in zip(final_checks[0::2], final_checks[1::2]):
                deps = sp.sympify(d).free_symbols | sp.sympify(m).free_symbols
                at = max((position[x] for x in deps if x in position), default=-1)
                if vector:
                    test = f"({printer.doprint(d)} > 0.0)" if sp.sympify(d - m) == 0 else \
                        f"({printer.doprint(d)} > {rtol}*({printer.doprint(m)}))"
                else:
                    test = f"!({printer.doprint(d)} > 0)" if sp.sympify(d - m) == 0 else \
                        f"!({printer.doprint(d)} > {rtol}*({printer.doprint(m)}))"
                pivot_checks.setdefault(at, []).append(test)
        if checked and vector:
            lines.append(f"{prefix}_vint all_ok = ({vreal}){{0.0}} == 0.0; /* every lane true */")

        def check_pivots(at):
            if at in pivot_checks:
                if vector:
                    lines.append("all_ok &= " + "\n        & ".join(pivot_checks[at]) + ";")
                else:
                    lines.append("if (" + "\n        || ".join(pivot_checks[at]) + ") {")
                    lines.append("    return 1; /* singular mass matrix at q (or q not finite) */")
                    lines.append("}")
        if gram:
            lines.append(f"{ltype} mass_s[{6 * (gram[1] - 1)}], mass_f[{6 * (gram[1] - 1)}];")
        if looped:
            lines.append(f"{ltype} fd_M[{n * n}], fd_b[{n}], fd_w[{n}], fd_d[{n}], fd_inv[{n}], fd_x[{n}];")

        def show(expr):
            """The printed expression; in the lanes function a number is broadcast to every lane."""
            text = printer.doprint(expr)
            if vector and not sp.sympify(expr).free_symbols:
                text = f"({vreal}){{0.0}} + {text}"
            return text

        # entries of the local arrays (the mass-matrix factors, forward dynamics' system) are stored
        # as soon as their last operand is computed, so that no value stays live (in a register or
        # spilled) until the end of the function; the caller's outputs are written at the end
        early: dict[int, list[str]] = {}
        late = []
        for (target, _), expr in zip(targets, final_outputs):
            if not target.startswith(LOCAL_ARRAYS):
                late.append((target, expr))
                continue
            deps = sp.sympify(expr).free_symbols
            at = max((position[x] for x in deps if x in position), default=-1)
            early.setdefault(at, []).append(f"{target} = {show(expr)};")
            ops += count_operations(expr)
            used |= deps

        def store_early(at):
            lines.extend(early.get(at, ()))
        check_pivots(-1)
        store_early(-1)
        for k, (sym, rhs) in enumerate(statements):
            lines.append(f"const {ltype} {names[sym]} = {show(rhs)};")
            ops += count_operations(rhs)
            used |= rhs.free_symbols
            check_pivots(k)
            store_early(k)
        store = f"({real})" if internal != scalar else ""
        if checked and not looped:
            used |= set().union(*(sp.sympify(e).free_symbols for e in final_checks))
            # compared in the type the results are computed in
            limit, fabs = (("(double)FLT_MAX" if scalar == "float" else "DBL_MAX"), "fabs") if internal == "double" \
                else ("FLT_MAX", "fabsf")
            results = []
            for target, expr in late:
                if isinstance(expr, sp.Symbol) and expr in names:
                    results.append(names[expr])
                else:
                    lines.append(f"const {ltype} {target} = {show(expr)};")
                    results.append(target)
                ops += count_operations(expr)
                used |= sp.sympify(expr).free_symbols
            if vector:
                lines.append("all_ok &= " + "\n        & ".join(f"({r} <= {limit}) & ({r} >= -{limit})" for r in results) + ";")
                for i, result in enumerate(results):
                    lines.append(f"{out_name}[{i}] = {result};")
                lines.append("*ok = all_ok;")
            else:
                lines.append("if (" + "\n        || ".join(f"!({fabs}({r}) <= {limit})" for r in results) + ") {")
                lines.append("    return 2; /* a result is NaN or out of range */")
                lines.append("}")
                for i, result in enumerate(results):
                    lines.append(f"{out_name}[{i}] = {store}{result};")
                lines.append("return 0;")
        else:
            for target, expr in late:
                text = show(expr)
                lines.append(f"{target} = {store}({text});" if store and not looped else f"{target} = {text};")
                ops += count_operations(expr)
                used |= sp.sympify(expr).free_symbols
        if gram:
            out, size = gram
            lines += _gram_loop(out, size, ltype, 4 if internal == "float" else 8, prefix, vector)
            ops += Counter({"mul": 6 * size * (size - 1) // 2, "add": 5 * size * (size - 1) // 2})
        if looped:
            solve, solve_ops = _looped_solve(n, ltype, printer.literal(rtol_value), printer.literal(1.0), vector,
                                             out_name, store, internal, scalar)
            lines += solve
            ops += solve_ops
        for target, source in aliases:
            lines.append(f"{target} = {source};")
        return lines, ops, used, printer.vector_functions

    lines, ops, used, _ = emit(vector=False)
    batch = None
    if batch_form:
        lanes, vector_functions, lanes_unused = None, set(), []
        if internal == "double" and precision == "double":
            allowed = (sp.sin, sp.cos, sp.sign)
            everything = [rhs for _, rhs in statements] + [sp.sympify(e) for e in list(final_outputs) + list(final_checks)]
            if not any(not isinstance(f, allowed) for e in everything for f in e.atoms(sp.Function)):
                try:
                    lanes, _, lanes_used, vector_functions = emit(vector=True)
                except VectorUnsupported:
                    lanes = None
                else:
                    lanes_unused = [a for a in [*inputs, *(["p"] if eqs.parameters else [])] if not any(
                        names.get(x, "").startswith(a + "[") for x in lanes_used)]
        sizes = [(argument.name, rows * cols) for part in parts
                 for argument, (rows, cols) in REGISTRY[part].argument_shapes(_dimensions(eqs))]
        batch = {"name": f"{name}_batch", "lanes": lanes, "lanes_unused": lanes_unused,
                 "vector_functions": sorted(vector_functions), "checked": checked,
                 "inputs": [(group, len(getattr(eqs, group))) for group in inputs],
                 "parameters": len(eqs.parameters), "outputs": sizes,
                 "scalar": f"{name}_checked" if checked else name, "trig": bool(angles)}

    args = [(f"const {real} *", group, ARG_DOCS[group], False) for group in inputs]
    if eqs.parameters:
        args.append((f"const {real} *", "p", ARG_DOCS["p"], False))
    args += [(f"{real} *", argument.name, argument.doc, True) for part in parts for argument in REGISTRY[part].arguments]
    unused = [a for _, a, _, is_out in args if not is_out and not any(
        names.get(s, "").startswith(cast + a + "[") for s in used)] + empty_outputs
    summary = (REGISTRY[name].summary_for(eqs.fd_method) if name in REGISTRY else _COMBINED_SUMMARIES[name]).replace("NAME", prefix)
    if internal != scalar:
        summary += (" Computed internally in double precision (precision 'mixed': float inputs and outputs), "
                    "for robots whose D is too ill-conditioned for float arithmetic.")
    trig_type = internal if angles else ""
    if checked:
        status = REGISTRY[name].status_for(eqs.fd_method)
        return CFunction(name=f"{name}_checked", summary=summary, args=args, lines=lines, ops=ops, unused=unused,
                         returns="int", returns_doc=status.format(rtol=rtol_value, real=scalar),
                         trig_type=trig_type, batch=batch, gram_loop=bool(gram))
    return CFunction(name=name, summary=summary, args=args, lines=lines, ops=ops, unused=unused,
                     trig_type=trig_type, batch=batch, gram_loop=bool(gram))


#: rows of L computed together by the looped LDL^T (independent sums for the pipeline)
ROWS = 4


def _looped_solve(n: int, ltype: str, rtol: str, one: str, vector: bool, out_name: str, store: str,
                  internal: str, scalar: str) -> tuple[list[str], Counter]:
    """C lines solving ``fd_M qdd = fd_b`` by an LDL^T loop (M's lower triangle given, L
    written over it), with the same pivot and finiteness checks as the unrolled
    form: status 1 when a pivot ``d_j`` is not above ``rtol * M_jj``, 2 when a result is not
    finite; qdd is written only on success.  ``vector``: the lanes function's form (checks
    gathered in ``all_ok``, ``*ok`` set).  Returns the lines and their operation counts."""
    if vector:
        check = ["    all_ok &= (d > " + rtol + "*fd_M[j * " + str(n) + " + j]);"]
    else:
        check = ["    if (!(d > " + rtol + "*fd_M[j * " + str(n) + " + j])) {",
                 "        return 1; /* singular mass matrix at q (or q not finite) */",
                 "    }"]
    lines = ["/* LDL^T of M (lower triangle of fd_M), left-looking: row j of L replaces row j */",
             f"for (int j = 0; j < {n}; ++j) {{",
             f"    {ltype} d = fd_M[j * {n} + j];",
             "    for (int k = 0; k < j; ++k) {",
             f"        fd_w[k] = fd_M[j * {n} + k]*fd_d[k]; /* L_jk d_k */",
             f"        d -= fd_M[j * {n} + k]*fd_w[k];",
             "    }",
             *check,
             "    fd_d[j] = d;",
             f"    fd_inv[j] = {one}/d;",
             "    int i = j + 1;",
             f"    /* {ROWS} rows at a time: {ROWS} independent sums, each in the order of the one-row loop */",
             f"    for (; i + {ROWS} <= {n}; i += {ROWS}) {{",
             f"        const {ltype} *r = fd_M + i * {n};",
             f"        {ltype} " + ", ".join(f"s{r} = r[{r * n} + j]" for r in range(ROWS)) + ";",
             "        for (int k = 0; k < j; ++k) {",
             f"            const {ltype} w = fd_w[k];",
             *[f"            s{r} -= r[{r * n} + k]*w;" for r in range(ROWS)],
             "        }",
             *[f"        fd_M[(i + {r}) * {n} + j] = s{r}*fd_inv[j];" for r in range(ROWS)],
             "    }",
             f"    for (; i < {n}; ++i) {{",
             f"        {ltype} s = fd_M[i * {n} + j];",
             "        for (int k = 0; k < j; ++k) {",
             f"            s -= fd_M[i * {n} + k]*fd_w[k];",
             "        }",
             f"        fd_M[i * {n} + j] = s*fd_inv[j];",
             "    }",
             "}",
             "/* L y = b, then D L^T x = y */",
             f"for (int i = 0; i < {n}; ++i) {{",
             f"    {ltype} y = fd_b[i];",
             "    for (int k = 0; k < i; ++k) {",
             f"        y -= fd_M[i * {n} + k]*fd_x[k];",
             "    }",
             "    fd_x[i] = y;",
             "}",
             f"for (int i = {n - 1}; i >= 0; --i) {{",
             f"    {ltype} x = fd_x[i]*fd_inv[i];",
             f"    for (int k = i + 1; k < {n}; ++k) {{",
             f"        x -= fd_M[k * {n} + i]*fd_x[k];",
             "    }",
             "    fd_x[i] = x;",
             "}"]
    limit, fabs = (("(double)FLT_MAX" if scalar == "float" else "DBL_MAX"), "fabs") if internal == "double" \
        else ("FLT_MAX", "fabsf")
    if vector:
        lines += [f"for (int i = 0; i < {n}; ++i) {{",
                  f"    all_ok &= (fd_x[i] <= {limit}) & (fd_x[i] >= -{limit});",
                  f"    {out_name}[i] = fd_x[i];",
                  "}",
                  "*ok = all_ok;"]
    else:
        lines += [f"for (int i = 0; i < {n}; ++i) {{",
                  f"    if (!({fabs}(fd_x[i]) <= {limit})) {{",
                  "        return 2; /* a result is NaN or out of range */",
                  "    }",
                  "}",
                  f"for (int i = 0; i < {n}; ++i) {{",
                  f"    {out_name}[i] = {store}fd_x[i];",
                  "}",
                  "return 0;"]
    mul = add = div = 0
    for j in range(n):
        div += 1
        mul += 2 * j + (n - 1 - j) * (j + 1)  # w and d; column j of L
        add += j + (n - 1 - j) * j
    mul += n * (n - 1) // 2 + n + n * (n - 1) // 2  # the two substitutions
    add += n * (n - 1)
    return lines, Counter({"mul": mul, "add": add, "div": div})


def _nominal_standard(robot):
    """The standard parameters' values as floats (None where a parameter has no value)."""
    from ..derive.regressor import standard_parameters
    values = robot.nominal_values()
    out = []
    for expr in standard_parameters(robot):
        expr = sp.sympify(expr).xreplace(values)
        out.append(float(expr) if expr.is_number else None)
    return out


def _regressor_parameters(eqs: Equations):
    """(index, name, meaning, nominal value or None) of each standard parameter."""
    from ..derive.regressor import LINK_PARAMETERS, PARAMETER_DOCS, parameter_names
    nominal = _nominal_standard(eqs.robot)
    names = parameter_names(eqs.robot)
    return [(k, names[k], PARAMETER_DOCS[LINK_PARAMETERS[k % len(LINK_PARAMETERS)]], nominal[k])
            for k in range(len(names))]


def _base_parameters(eqs: Equations):
    """(index, name, expression text, nominal value or None) of each base parameter."""
    from ..derive.regressor import parameter_names
    nominal = dict(zip(parameter_names(eqs.robot), _nominal_standard(eqs.robot)))
    rows = []
    for k, (name, expr) in enumerate(eqs.base_parameters):
        value = None
        if all(nominal.get(s.name) is not None for s in expr.free_symbols):
            value = float(expr.xreplace({s: nominal[s.name] for s in expr.free_symbols}))
        text = sp.sstr(expr.xreplace({f: sp.Float(f, 10) for f in expr.atoms(sp.Float)}), full_prec=False)
        rows.append((k, name, text, value))
    return rows


def generate_c(eqs: Equations, functions=None, precision: str = "double", header_only: bool = False,
               source_name: str = "", source_hash: str = "", notes: tuple[str, ...] = (),
               progress=None, size_report=None, batch: bool = False) -> dict[str, str]:
    """Render ``NAME_dynamics.h`` and ``NAME_dynamics.c`` (or one header of static inline
    functions when ``header_only``).  Returns ``{file name: text}``.  ``progress`` (optional) is
    called with a short text as each function's C is built.  ``size_report`` (optional): called
    with the rendered files, returns an object with ``sizes`` ({C function name: (text bytes,
    stack bytes)}), ``doubles`` (double-precision routines referenced) and ``toolchain`` (what
    measured them); the header then documents each function's size and stack use.  ``batch``:
    also emit ``NAME_<function>_batch(count, ...)`` over arrays of states (vectorized in double
    precision with GCC/Clang vector types, a loop over the scalar function otherwise)."""
    functions = [f for f in ALL_OUTPUTS if f in (functions or eqs.output_names)]
    prefix = eqs.robot.name
    built = []
    for f in functions:
        if progress is not None:
            progress(f"{prefix}: C for {f}")
        built.extend(build_functions(eqs, f, precision, prefix, batch))
    for combined, parts in COMBINED.items():
        if all(part in functions for part in parts):
            built.append(build_function(eqs, combined, precision, prefix, batch))
    externals = [f"{prefix}_{f.name}" for f in built] + [f"{prefix}_{f.batch['name']}" for f in built if f.batch]
    if len({e[:31] for e in externals}) < len(externals):
        warn(f"robot name '{prefix}': the generated function names ({', '.join(externals)}) are not "
             "distinct in their first 31 characters, all that C99 guarantees a linker to compare; "
             "a shorter robot name is safer with old toolchains")
    robot = eqs.robot
    context = {
        "prefix": prefix,
        "guard": f"{prefix.upper()}_DYNAMICS_H",
        "version": __version__,
        "source_name": source_label(source_name or robot.source),
        "source_hash": source_hash or robot.source_hash,
        "method": eqs.method + {"aba": "; forward dynamics by the articulated-body algorithm",
                                "ldlt": "; forward dynamics by LDL^T of D"}.get(eqs.fd_method, "")
        + ("; inverse dynamics in the base parameters" if eqs.parameter_form == "base"
           and "inverse_dynamics" in functions else ""),
        "precision": precision,
        "real": scalar_type(precision),
        "dof": robot.dof,
        "convention": robot.convention,
        "parameters": [(k, s.name, "runtime parameter" if v is not None else "runtime parameter, no nominal value",
                        (repr(float(v)) if v is not None else None), parameter_uses(robot, s))
                       for k, (s, v) in enumerate(zip(robot.parameters, robot.nominal))],
        "constants": model_constants(robot),
        "joints": [(k + 1, link.name, link.joint, link.actuated) for k, link in enumerate(robot.links)],
        "reaction": ([f"{j + 1} ({robot.links[j].name})" for j in robot.actuated_joints]
                     if "reaction_map" in functions else None),
        "functions": built,
        "header_only": header_only,
        "notes": [comment_text(note) for note in notes],
        "math_header": True,
        "float_header": any(f.returns == "int" for f in built),
        "size_target": "",
        "size_doubles": "",
        "regressor_parameters": _regressor_parameters(eqs) if "regressor" in functions else [],
        "base_parameters": _base_parameters(eqs) if "base_regressor" in functions else [],
        "trig_double": any(f.trig_type == "double" for f in built) or any(
            f.batch and f.batch["lanes"] is not None and f.batch["trig"] for f in built),
        "vector_trig": any(f.batch and f.batch["lanes"] is not None and f.batch["trig"] for f in built),
        "trig_float": any(f.trig_type == "float" for f in built),
        "gram_vector": any(f.gram_loop for f in built),
        "batch": batch,
        "vector": any(f.batch and f.batch["lanes"] is not None for f in built),
        "vector_functions": sorted(set().union(*(f.batch["vector_functions"] for f in built if f.batch))),
    }
    env = template_environment()
    header = env.get_template("dynamics.h.j2").render(**context)
    files = {f"{prefix}_dynamics.h": header}
    if not header_only:
        files[f"{prefix}_dynamics.c"] = env.get_template("dynamics.c.j2").render(**context)
    if size_report is not None and not header_only:
        report = size_report(dict(files))
        for f in built:
            text, stack = report.sizes.get(f"{prefix}_{f.name}", (None, None))
            if text is not None:
                f.size_text = f"Cortex-M4: {text} bytes of code, {stack} bytes of stack (measured as stated at the top)."
        context["size_target"] = report.toolchain
        context["size_doubles"] = ", ".join(report.doubles) or "none"
        files[f"{prefix}_dynamics.h"] = env.get_template("dynamics.h.j2").render(**context)
    return files
