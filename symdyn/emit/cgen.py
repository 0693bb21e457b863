"""C99 emitter: lays the derived equations out as straight-line C through Jinja2 templates.

This module derives nothing: it takes an :class:`~symdyn.derive.equations.Equations`, keeps the
intermediate assignments each function needs (dead code removed), eliminates further common
subexpressions, folds constants, prints with :mod:`symdyn.emit.cprinter` and renders the templates in
``templates/`` (shipped in the wheel as ``symdyn.templates``).
"""

from __future__ import annotations

import re

from collections import Counter
from dataclasses import dataclass, field

import sympy as sp

from .._version import __version__
from ..model.errors import warn
from .cbody import ARGUMENTS, QUATERNION, BodyContext, fma_macro, product_loop, write_body
from .cplan import (FunctionPlan, Target, collect_targets, minv_targets, product_targets, reduce_targets,
                    tangent_width)
from .cprinter import CPrinter, VectorUnsupported
from .emission import banner_fields, comment_text, constant_rows, constant_text, source_label, template_environment
from ..derive.equations import Equations
from ..model.robot import JACOBIAN_ROWS
from ..model.tolerances import pivot_rtol
from ..derive.configuration import SERIES_BELOW
from ..model.outputs import (ALL_OUTPUTS, CENTROIDAL_OUTPUTS, COMBINED, CONFIGURATION_OUTPUTS, CONTACT_SOLVED, EXTERNAL_OUTPUTS, FRAME_OUTPUTS, COMBINED_SPECS, REGISTRY, TASK_OUTPUTS, STATUS_CODES,
                             INPUT_GROUPS, factors_mass_matrix)

ARG_DOCS = {
    "q": "joint positions, N (rad for revolute, m for prismatic joints)",
    "qd": "joint velocities, N (rad/s or m/s)",
    "qdd": "joint accelerations, N (rad/s^2 or m/s^2)",
    "tau": "joint torques/forces, N (N m or N)",
    "v": "a displacement of the joints, N (rad or m): velocity times a time step",
    "q1": "joint positions of a second configuration, N (rad or m)",
    "f": "external forces at the contacts, NC, laid out as the contact forces (listed above): a point's force (N), "
         "a sole's force then moment (N m), on the robot, world axes at each frame's origin",
    "restitution": "restitution of the impact, 1 entry: 0 the contacts stop (Pinocchio's r_coeff), 1 they bounce back",
    "p": "runtime parameters, NP, in the order listed above",
}
#: the arguments' documentation for a floating base (Pinocchio's free-flyer layout)
FLOATING_ARG_DOCS = {
    **ARG_DOCS,
    "q": "configuration, NQ = NV + 1: the base position in the world (m), its orientation as a quaternion x, y, z, "
         "w (any nonzero scale: it is normalized; q and -q are the same pose), then the joint positions (rad or m)",
    "qd": "velocity, NV: the base's linear velocity (m/s) and angular velocity (rad/s), both in the base frame, "
          "then the joint velocities (rad/s or m/s)",
    "qdd": "acceleration, NV: the derivative of qd (the base's spatial acceleration in its frame, m/s^2 and "
           "rad/s^2), then the joint accelerations",
    "tau": "generalized forces, NV: the force (N) and moment (N m, about the base origin) on the base, in the base "
           "frame (zero for a robot in flight), then the joint torques/forces",
    "v": "tangent vector, NV: a displacement laid out as qd (velocity times a time step): the base's (m, rad, in "
         "its frame), then the joints'",
    "q1": "a second configuration, NQ, laid out as q (its quaternion of any nonzero scale)",
}

#: precisions of the generated C: double, float (float all the way: no double operation, for
#: single-precision FPUs), mixed (float arguments; every function that solves with the mass
#: matrix, forward dynamics first, computed in double inside)
PRECISION_CHOICES = ("double", "float", "mixed")


def scalar_type(precision: str) -> str:
    """The C type of the arguments for a precision."""
    if precision not in PRECISION_CHOICES:
        raise ValueError(f"precision must be one of {', '.join(PRECISION_CHOICES)}, not {precision!r}")
    return "double" if precision == "double" else "float"


_COMBINED_SUMMARIES = {c.name: c.summary for c in COMBINED_SPECS}


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
    #: whether the body has the mass matrix's off-diagonal loop or the Coriolis matrix's (see
    #: symdyn.emit.cbody.gram_loop, coriolis_loop): they use vector types where there are some
    gram_loop: bool = False
    #: a long body's parts, each ``(returns, extra parameters, lines)``: functions of their own,
    #: called in order from ``lines`` (symdyn.emit.cbody.SPLIT_FROM_STATEMENTS)
    parts: list = field(default_factory=list)
    #: the type ("double", "float") of its fused multiply-adds (symdyn.emit.cbody.fma_macro), or
    #: "" when it has none
    fma_type: str = ""

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


def _scaled_quaternions(eqs: Equations, reduced, names: dict, inputs) -> tuple[tuple[str, tuple[str, ...]], ...]:
    """For each configuration among ``inputs`` (q, q1) whose floating base's quaternion (entries
    3..6) the body reads: the local array of its scaled copy and the C text of its four entries,
    each name then pointing at the copy (:meth:`BodyWriter._quaternion_block`); else ``()``."""
    if not eqs.robot.floating:
        return ()
    read = set().union(*(sp.sympify(rhs).free_symbols for _, rhs in reduced.statements),
                       *(sp.sympify(e).free_symbols for e in list(reduced.outputs) + reduced.checks))
    blocks = []
    for group in ("q", "q1"):
        symbols = getattr(eqs, group)[3:7]
        if group not in inputs or not read & set(symbols):
            continue
        array = QUATERNION if group == "q" else f"{QUATERNION}1"
        blocks.append((array, tuple(names[sym] for sym in symbols)))
        for k, sym in enumerate(symbols):
            names[sym] = f"{array}[{k}]"
    return tuple(blocks)


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
    """The C function of one output or combined function (forward dynamics: the checked
    function), in three stages: its targets (:func:`~symdyn.emit.cplan.collect_targets`), their
    statements (:func:`~symdyn.emit.cplan.reduce_targets`), the body's lines
    (:func:`~symdyn.emit.cbody.write_body`); with ``batch_form``, also the batch form over arrays
    of states (``CFunction.batch``)."""
    plan = collect_targets(eqs, name)
    if plan.products and len(plan.products[1]) > 1:  # both derivatives: they share each stage
        staged = _staged_function(eqs, plan, precision, prefix, batch_form)
        if staged is not None:
            return staged
    reduced, context, body, group_of = _body(eqs, plan, precision, prefix)
    real, scalar, internal, angles = context.real, context.scalar, context.internal, context.angles
    args = _arguments(eqs, plan, real)
    read = {group_of[s] for s in body.used if s in group_of}
    unused = [a for _, a, _, is_out in args if not is_out and a not in read] + plan.empty_outputs
    batch = _batch_form(eqs, plan, reduced, context, group_of, precision) if batch_form else None
    fd_variant = eqs.fd_method + ("-loops" if plan.sweeps is not None else "")
    summary = (REGISTRY[name].summary_for(fd_variant) if name in REGISTRY
               else _COMBINED_SUMMARIES[name]).replace("NAME", prefix)
    summary += _tangent_note(plan.tangents) + (FUSED_NOTE if body.fma else "")
    if internal != scalar:
        summary += (" Computed internally in double precision (precision 'mixed': float inputs and outputs), "
                    "for robots whose D is too ill-conditioned for float arithmetic.")
    lines, parts = body.lines, []
    if body.parts:  # a long body in parts (symdyn.emit.cbody.SPLIT_FROM_STATEMENTS)
        own = checked_name(name) if plan.checked else name
        names = ", ".join(a for _, a, _, _ in args)
        lines = [re.sub(r"@PART(\d+)@", lambda m: f"{prefix}_{own}_part{m.group(1)}", line.replace(ARGUMENTS, names))
                 for line in lines]
        parts = [(returns, ", ".join(extra)) + (part_lines,) for returns, extra, part_lines in body.parts]
    common = dict(summary=summary, args=args, lines=lines, parts=parts, ops=body.ops, unused=unused,
                  trig_type=internal if angles else "", batch=batch, gram_loop=bool(plan.gram or plan.coriolis),
                  fma_type=internal if body.fma else "")
    if plan.checked:
        status = REGISTRY[plan.parts[0]].status_for(fd_variant if name == "forward_dynamics" else "")
        return CFunction(name=checked_name(name), returns="int",
                         returns_doc=status.format(rtol=context.rtol, real=scalar, prefix=prefix.upper()), **common)
    return CFunction(name=name, **common)


#: the header's word on a function with fused multiply-adds (templates/fma.j2): the
#: forward-dynamics derivatives' loops, and every sum of products in their two stages and in
#: the bodies of FUSE_FROM_STATEMENTS statements or more
FUSED_NOTE = " Fused multiply-adds where the target has a fast fma (see the top of this file)."


def _tangent_note(tangents) -> str:
    """The header's word on derivatives written as loops over vector tangents (or "")."""
    if tangents is None:
        return ""
    width = tangent_width(tangents.tangents.directions)
    return (f" The derivatives are computed as vector tangents: one loop over the {width} lanes of the directions "
            "(padding included) per statement of the recursion, so that the code grows with the statements, not "
            "with their number times the joints; the cost counts every lane.")


def _arguments(eqs: Equations, plan, real: str) -> list[tuple[str, str, str, bool]]:
    """A function's parameters ``(C type, name, doc, is output)``: its inputs, ``p`` when the
    robot has runtime parameters, then each part's output arguments."""
    docs = FLOATING_ARG_DOCS if eqs.robot.floating else ARG_DOCS
    args = [(f"const {real} *", group, docs[group], False) for group in plan.inputs]
    if eqs.parameters:
        args.append((f"const {real} *", "p", ARG_DOCS["p"], False))
    return args + [(f"{real} *", argument.name, argument.doc, True)
                   for part in plan.parts for argument in REGISTRY[part].arguments]


#: a body of this many statements or more prints every sum of products with the fused
#: multiply-add macro (templates/fma.j2), whatever the function: long straight-line code runs at
#: the speed of its instruction fetch, and fused it is shorter (TALOS reduced, floating, gcc -O3
#: -march=native: inverse dynamics 1541 statements, 46 -> 32 kB of code, 1278 -> 577 ns; forward
#: dynamics 4127 -> 3409; the mass matrix 1481 -> 1362).  Shorter bodies stay plain: a fused sum
#: is a longer dependency chain where an add has half an FMA's latency (the 7-joint arms'
#: inverse-dynamics derivatives, 300-850 statements, lost up to 19%; docs/benchmarks.md)
FUSE_FROM_STATEMENTS = 1500


def _body(eqs: Equations, plan, precision: str, prefix: str, given=None, given_arrays=frozenset(), fused=False):
    """Stages 2 and 3 of one plan: ``(reduced, context, body, group_of)``; ``given`` maps the
    plan's leaves to their C names; ``given_arrays``: the scratch arrays the body is handed
    (:attr:`BodyContext.given_arrays`); ``fused``: every sum of products by the fused
    multiply-add macro (:attr:`BodyContext.fused`; also for any body of
    :data:`FUSE_FROM_STATEMENTS` statements or more)."""
    reduced = reduce_targets(eqs, plan)
    # precision "mixed": float arguments everywhere, but every function that solves with D
    # computed inside in double (for robots whose D is too ill-conditioned for float: forward
    # dynamics, its derivatives, M^-1, the task-space functions); "float" is float all the way.
    scalar = scalar_type(precision)
    internal = "double" if (precision == "mixed" and factors_mass_matrix(plan.name)) else scalar
    real = f"{prefix}_real"
    cast = "(double)" if internal != scalar else ""
    names: dict[sp.Symbol, str] = dict(given or {})
    group_of: dict[sp.Symbol, str] = {}  # input symbol -> its argument
    for group in plan.inputs:
        for k, sym in enumerate(getattr(eqs, group)):
            names[sym], group_of[sym] = f"{cast}{group}[{k}]", group
    for k, sym in enumerate(eqs.parameters):
        names[sym], group_of[sym] = f"{cast}p[{k}]", "p"
    quaternion = _scaled_quaternions(eqs, reduced, names, plan.inputs)
    for sym, _ in reduced.statements:
        names[sym] = sym.name.lstrip("_")
    angles = _hoisted_angles(reduced.statements, list(reduced.outputs) + reduced.checks,
                             {sym for sym, _ in reduced.statements})
    context = BodyContext(prefix=prefix, names=names, angles=angles, internal=internal, scalar=scalar,
                          local_type=real if internal == scalar else internal, real=real, n=eqs.n,
                          rtol=pivot_rtol(internal),  # checked in the arithmetic the pivots are computed in
                          sizes={group: len(getattr(eqs, group)) for group in INPUT_GROUPS},
                          given_arrays=frozenset(given_arrays),
                          fused=fused or len(reduced.statements) >= FUSE_FROM_STATEMENTS, quaternion=quaternion)
    return reduced, context, write_body(plan, reduced, context), group_of


def _staged_function(eqs: Equations, plan, precision: str, prefix: str, batch_form: bool) -> CFunction | None:
    """A function with forward-dynamics derivatives, in two stages of its own (static parts)
    and the product loop: part 1 factors M and gives M^-1 and qdd (``fdd_m``, ``fdd_a``; the
    pivot checks and statuses), part 2 the derivatives of inverse dynamics at that qdd
    (``fdd_q``, ``fdd_v``), then ``-Minv dtau/dx``.  Each part's register allocation is its own:
    puma560's forward_dynamics_derivatives 1035 -> about 800 ns, the panda's 2900 -> 2500 (gcc -O3
    -march=native), against one body.  None when a stage is long enough to be split itself."""
    n, blocks, minv, stride, _ = plan.products
    qdd = eqs.inverse_products[3]
    solve = FunctionPlan(plan.name, plan.parts, plan.inputs, plan.out_name, checked=True,
                         pivots=plan.pivots, pivot_codes=plan.pivot_codes)
    solve.targets = minv_targets(eqs) + [Target(f"fdd_a[{i}]", qdd[i], True) for i in range(n)]
    targets, tangents = product_targets(eqs, plan.parts)
    tangent = FunctionPlan(plan.name, plan.parts, tuple(g for g in plan.inputs if g != "tau"), plan.out_name,
                           leaves=frozenset(qdd), targets=targets, tangents=tangents)
    # both stages fuse their scalar statements too (the loops always do): the panda 1241 -> 1164
    # ns; in the other functions that loses (a single dtau/dq: iiwa14 391 -> 437 ns, the panda
    # 481 -> 512: a long sum of products fused is a chain of FMAs, and on this machine's cores an
    # add has half an FMA's latency, 0.67 against 1.35 ns)
    reduced, context, first, group_of = _body(eqs, solve, precision, prefix, fused=True)
    # the tangents' scratch (kB) lives in the caller's frame and part 2 reads it through a pointer:
    # the Panda 1262 -> 1223 ns (gcc -O3 -march=native), part 2's frame and its addresses smaller
    _, _, second, _ = _body(eqs, tangent, precision, prefix, {s: f"fdd_a[{k}]" for k, s in enumerate(qdd)},
                            given_arrays={"dv_t"}, fused=True)
    if first.parts or second.parts:
        return None
    ltype, real = context.local_type, context.real
    args = _arguments(eqs, plan, real)
    names = ", ".join(a for _, a, _, _ in args)
    own = f"{prefix}_{plan.name}"
    arrays = ([("fdd_m", n * n), ("fdd_a", n)] + [(array, n * stride) for array, _ in blocks]
              + [("fdd_r", len(blocks) * n * stride)] + second.given)
    store = f"({real})" if context.internal != context.scalar else ""
    loop, loop_ops = product_loop(plan.products, store, context.internal, context.scalar, fma_macro(prefix), prefix)
    lines = ([f"{ltype} " + ", ".join(f"{a}[{size}]" for a, size in arrays) + ";",
              f"const int status = {own}_part1({names}, fdd_m, fdd_a);",
              "if (status != 0) {", "    return status;", "}",
              f"{own}_part2({names}, fdd_a, {', '.join([a for a, _ in blocks] + [a for a, _ in second.given])});"] + loop)
    parts = [("int", f"{ltype} *restrict fdd_m, {ltype} *restrict fdd_a", first.lines),
             ("void", f"const {ltype} *restrict fdd_a, " + ", ".join(f"{ltype} *restrict {a}" for a, _ in list(blocks) + second.given),
              ["(void)fdd_a; /* (dqdd/dqd alone: dtau/dqd does not depend on qdd) */"] + second.lines)]
    batch = _batch_form(eqs, plan, reduced, context, group_of, precision) if batch_form else None
    summary = _COMBINED_SUMMARIES[plan.name] if plan.name in _COMBINED_SUMMARIES else REGISTRY[plan.name].summary
    summary += _tangent_note(tangents) + FUSED_NOTE
    status = REGISTRY[plan.parts[0]].status
    return CFunction(name=plan.name, summary=summary.replace("NAME", prefix), args=args, lines=lines, parts=parts,
                     ops=first.ops + second.ops + loop_ops, unused=[], trig_type=context.internal if context.angles else "",
                     batch=batch, returns="int", fma_type=context.internal,
                     returns_doc=status.format(rtol=context.rtol, real=context.scalar, prefix=prefix.upper()))


def _batch_form(eqs: Equations, plan, reduced, context: BodyContext, group_of, precision: str) -> dict:
    """What the batch template needs: the lanes function (vector types over states, double
    precision only, when every function called has a vector form) or None for a loop over the
    scalar function, and the arrays' sizes."""
    lanes, vector_functions, lanes_unused = None, set(), []
    # (a fused body has no vector form: GCC's vector types have no fused multiply-add, and the
    # batch must give the scalar function's results bit for bit)
    if context.internal == "double" and precision == "double" and not context.fused:
        allowed = (sp.sin, sp.cos, sp.sign)
        everything = [rhs for _, rhs in reduced.statements] + [sp.sympify(e) for e in list(reduced.outputs) + reduced.checks]
        if not any(not isinstance(f, allowed) for e in everything for f in e.atoms(sp.Function)):
            try:
                lanes_body = write_body(plan, reduced, context, vector=True)
            except VectorUnsupported:
                pass
            else:
                lanes, vector_functions = lanes_body.lines, lanes_body.vector_functions
                read = {group_of[s] for s in lanes_body.used if s in group_of}
                lanes_unused = [a for a in [*plan.inputs, *(["p"] if eqs.parameters else [])] if a not in read]
    sizes = [(argument.name, rows * cols) for part in plan.parts
             for argument, (rows, cols) in REGISTRY[part].argument_shapes(eqs.dimensions)]
    return {"name": f"{plan.name}_batch", "lanes": lanes, "lanes_unused": lanes_unused,
            "vector_functions": sorted(vector_functions), "checked": plan.checked,
            "inputs": [(group, len(getattr(eqs, group))) for group in plan.inputs],
            "parameters": len(eqs.parameters), "outputs": sizes,
            "scalar": checked_name(plan.name) if plan.checked else plan.name, "trig": bool(context.angles)}


def _task_context(eqs: Equations, precision: str) -> dict:
    """What the header says about the task of the task-space functions: its rows and the
    default of the singularity tolerance macro."""
    rows = eqs.robot.task_rows
    return {"count": len(rows), "rows": ", ".join(f"{row} ({JACOBIAN_ROWS[row]})" for row in rows),
            "rtol": repr(pivot_rtol(_checked_arithmetic(precision)))}


def _correction_lines(contact) -> list[str]:
    """The header's lines on a contact's Baumgarte correction: its equation, gains and reference."""
    def shown(e):
        return f"{float(e):.17g}" if sp.sympify(e).is_number else str(e)
    sole = contact.kind == "6d"
    held = " - kp X log6(M^-1 M_ref)" if sole else " + kp (p - reference)"
    lines = ["  Baumgarte correction (Pinocchio's corrector, one gain on every axis): J qdd + gamma"
             + (" + kd v" if contact.kd != 0 else "") + (held if contact.kp != 0 else "") + " = 0,",
             (f"  v the frame's velocity, M its placement, X = diag(R, R) its rotation, kp = {shown(contact.kp)} 1/s^2, "
              if sole else f"  v, p the point's velocity and position, kp = {shown(contact.kp)} 1/s^2, ")
             + f"kd = {shown(contact.kd)} 1/s"]
    if contact.kp != 0 and sole:
        lines.append(f"  M_ref: origin ({', '.join(shown(e) for e in contact.reference[:3])}) m, rotation roll, pitch, "
                     f"yaw ({', '.join(shown(e) for e in contact.reference[3:])}) rad about the fixed world axes")
    elif contact.kp != 0:
        lines.append(f"  reference = ({', '.join(shown(e) for e in contact.reference)}) m, world coordinates")
    return lines


def _contact_context(eqs: Equations, precision: str) -> dict:
    """What the header says about the contact set: each contact's frame, kind and entries of
    the forces, their count and the default of the dependence tolerance macro."""
    robot, lines, at = eqs.robot, [], 0
    for contact in robot.contacts:
        frame = robot.frames[contact.frame]
        what = {"3d": "a point held: force (N) x, y, z", "6d": "a sole held: force (N) x, y, z, then moment (N m) x, y, z"}.get(
            contact.kind, f"a point held in the {contact.kind} plane: force (N) {', '.join(contact.kind)}")
        lines.append(f"lambda[{at}..{at + contact.rows - 1}]: {frame.name} ({contact.kind}, {what})")
        if contact.corrected:
            lines += _correction_lines(contact)
        at += contact.rows
    return {"count": robot.contact_rows, "lines": lines, "rtol": repr(pivot_rtol(_checked_arithmetic(precision)))}


def _checked_arithmetic(precision: str) -> str:
    """The arithmetic the status-returning functions compute their pivots in: float in float,
    double in double and in mixed (which computes every function that solves with D in double)."""
    return "float" if precision == "float" else "double"


def _contract_context(eqs: Equations, precision: str, built) -> dict:
    """The header's status codes (:data:`STATUS_CODES`, the task's only with task-space
    functions; none when no function returns a status) and the pivot tolerance's default, in
    the arithmetic the pivots are computed in (double in mixed precision)."""
    if not any(f.returns == "int" for f in built):
        return {"statuses": [], "pivot_rtol": "", "pivot_rtol_text": ""}
    task = any(f.name in TASK_OUTPUTS or f.name == "task_space" for f in built)
    contact = any(part in CONTACT_SOLVED for f in built for part in COMBINED.get(f.name, (f.name,)))
    internal = _checked_arithmetic(precision)
    text = eqs.robot.name.upper()
    return {"statuses": [(name, value, doc.replace("NAME_", f"{text}_")) for name, (value, doc) in STATUS_CODES.items()
                         if (task or name != "TASK_SINGULAR") and (contact or name != "CONTACT_SINGULAR")],
            "pivot_rtol": CPrinter({}, internal).literal(pivot_rtol(internal)),
            "pivot_rtol_text": repr(pivot_rtol(internal))}


def _status_list(built, prefix: str) -> str:
    """The functions that return a status, for the header's note on inputs: "the task-space
    functions", the others by name, forward dynamics' checked function last."""
    names = [f.name for f in built if f.returns == "int"]
    items = (["the task-space functions"] if any(n in TASK_OUTPUTS or n == "task_space" for n in names) else []) + [
        f"{prefix}_{n}" for n in names if n not in TASK_OUTPUTS and n != "task_space" and n != "forward_dynamics_checked"]
    items += [f"{prefix}_forward_dynamics_checked"] if "forward_dynamics_checked" in names else []
    return ", ".join(items[:-1]) + " and " + items[-1] if len(items) > 1 else "".join(items)


def checked_name(name: str) -> str:
    """The name of the function that returns a status: forward dynamics' is
    ``forward_dynamics_checked`` (``forward_dynamics`` is the plain call beside it); the
    task-space functions return their status themselves."""
    return f"{name}_checked" if name == "forward_dynamics" else name


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


def _joint_rows(robot) -> list[tuple]:
    """The header's list of the joints, one per coordinate: ``(index from 1, name, type,
    actuated, where it hangs and the mimic joints that follow it)``."""
    parents, rows = robot.parent_indices, []
    coordinates = {j: k for k, j in enumerate(robot.coordinate_links)}
    for k, j in enumerate(robot.coordinate_links):
        link, up = robot.links[j], parents[j]
        where = ("" if not robot.is_tree else ", on the base" if up < 0
                 else f", on joint {coordinates[up] + 1} ({robot.links[up].name})" if up in coordinates
                 else f", on mimic joint {robot.links[up].name}")
        followers = [f"{other.name} = {constant_text(other.mimic.multiplier)} * q + {constant_text(other.mimic.offset)}"
                     for other in robot.links if other.mimic is not None and other.mimic.leader == j]
        if followers:
            where += f"; mimic joints that follow it: {', '.join(followers)}"
        rows.append((k + 1, link.name, link.joint, link.actuated, where))
    return rows


def _total_mass(robot) -> str | None:
    """The robot's total mass (every link, and a floating base's body) as a C literal, or None
    when it depends on runtime parameters."""
    total = sp.sympify(sum((link.mass for link in robot.links), robot.base_inertia.mass if robot.floating else 0))
    return repr(float(total)) if total.is_number else None


#: C of more bytes than this is written as several files, each a translation unit of whole
#: functions of at most about this size (a single function larger has a file of its own): gcc keeps
#: every function of a translation unit in memory until it has emitted the last one, about 130 MB
#: per MB of this C at -O2 (TIAGo dual's 6.9 MB in one file: 710 MB, 430 MB already at -O0;
#: TIAGo's 2.7 MB: 352 MB); docs/benchmarks.md, "Parts by lines, values carried where used"
C_FILE_BYTES = 3_000_000


def generate_c(eqs: Equations, functions=None, precision: str = "double", header_only: bool = False,
               source_name: str = "", source_hash: str = "", notes: tuple[str, ...] = (),
               progress=None, size_report=None, batch: bool = False, locked=(),
               file_bytes: int | None = C_FILE_BYTES) -> dict[str, str]:
    """Render ``NAME_dynamics.h`` and ``NAME_dynamics.c`` (or one header of static inline
    functions when ``header_only``; C of more than ``file_bytes`` as several files,
    :func:`_source_files`).  Returns ``{file name: text}``.  The header lists every
    model constant folded into the code (:func:`~symdyn.emit.emission.constant_rows`; ``locked``:
    the joints a scene locked, :attr:`symdyn.model.scene.Scene.locked`).  ``progress`` (optional) is
    called with a short text as each function's C is built.  ``size_report`` (optional): called
    with the rendered files, returns an object with ``sizes`` ({C function name: (text bytes,
    stack bytes)}), ``doubles`` (double-precision routines referenced), ``toolchain`` (what
    measured them) and ``command`` (the exact compile command); the header then documents each
    function's size and stack use.  ``batch``:
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
    clashing = [e for e in externals if sum(other[:31] == e[:31] for other in externals) > 1]
    if clashing:
        warn(f"robot name '{prefix}': the generated function names {', '.join(clashing)} are not "
             "distinct in their first 31 characters, all that C99 guarantees a linker to compare; "
             "a shorter robot name is safer with old toolchains")
    context = _file_context(eqs, functions, precision, built, header_only, source_name, source_hash, notes, locked,
                            batch)
    context.update(banner_fields(prefix, precision, context["method"], eqs.robot))
    env = template_environment()
    sources = {} if header_only else _source_files(env, context, built, prefix, file_bytes)
    if len(sources) > 1:
        names = ", ".join(sources)
        size = sum(len(text) for text in sources.values()) / 1e6
        warn(f"{prefix}: the C is {size:.1f} MB, written as {len(sources)} files of at most about "
             f"{file_bytes / 1e6:.0f} MB each (one file would need more compiler memory): compile all of {names}")
        context["notes"] = context["notes"] + [comment_text(
            f"the C is in {len(sources)} files ({names}), each a translation unit of at most about "
            f"{file_bytes / 1e6:.0f} MB: compile and link all of them")]
    files = {f"{prefix}_dynamics.h": env.get_template("dynamics.h.j2").render(**context), **sources}
    if size_report is not None and not header_only:
        report = size_report(dict(files))
        for f in built:
            text, stack = report.sizes.get(f"{prefix}_{f.name}", (None, None))
            if text is not None:
                f.size_text = f"Cortex-M4: {text} bytes of code, {stack} bytes of stack (measured as stated at the top)."
        context["size_target"] = comment_text(report.toolchain)
        context["size_command"] = comment_text(getattr(report, "command", ""))
        context["size_doubles"] = ", ".join(report.doubles) or "none"
        files[f"{prefix}_dynamics.h"] = env.get_template("dynamics.h.j2").render(**context)
    return files


def _file_context(eqs: Equations, functions, precision: str, built, header_only: bool, source_name: str,
                  source_hash: str, notes, locked, batch: bool) -> dict:
    """The templates' context of the generated files (templates/dynamics.h.j2 and .c.j2): the
    robot's description for the header, the built functions (``built``) and what they need."""
    prefix = eqs.robot.name
    robot = eqs.robot
    return {
        "prefix": prefix,
        "guard": f"{prefix.upper()}_DYNAMICS_H",
        "version": __version__,
        "source_name": source_label(source_name or robot.source),
        "source_hash": source_hash or robot.source_hash,
        "method": eqs.method + {"aba": "; forward dynamics by the articulated-body algorithm"
                                + (" as loops over the joints" if eqs.fd_loops else ""),
                                "ldlt": "; forward dynamics by L^T D L of the tree's D" if robot.is_tree
                                else "; forward dynamics by LDL^T of D"}.get(eqs.fd_method, "")
        + ("; floating base (free-flyer)" if robot.floating else "")
        + ("; inverse dynamics in the base parameters" if eqs.parameter_form == "base"
           and "inverse_dynamics" in functions else ""),
        "precision": precision,
        "real": scalar_type(precision),
        "dof": eqs.n,
        "nq": eqs.nq,
        "floating": robot.floating,
        "convention": robot.convention,
        "parameters": [(k, s.name, "runtime parameter" if v is not None else "runtime parameter, no nominal value",
                        (repr(float(v)) if v is not None else None), parameter_uses(robot, s))
                       for k, (s, v) in enumerate(zip(robot.parameters, robot.nominal))],
        "constants": constant_rows(robot, locked),
        "fixed_transforms": robot.tool_fixed is not None or any(link.fixed is not None for link in robot.links),
        "joints": _joint_rows(robot),
        "tree": robot.is_tree,
        "total_mass": _total_mass(robot) if any(f in CENTROIDAL_OUTPUTS for f in functions) else None,
        "configuration": str(SERIES_BELOW) if any(f in CONFIGURATION_OUTPUTS for f in functions) else "",
        "frames": ([(k, frame.name, "the base" if frame.link < 0 else f"link {frame.link + 1} ({robot.links[frame.link].name})",
                     "its own frame" if frame.pose is None else "fixed in it")
                    for k, frame in enumerate(robot.frames)] if any(f in FRAME_OUTPUTS for f in functions) else []),
        "reaction": ([f"{j + 1} ({robot.links[j].name})" for j in robot.actuated_joints]
                     if "reaction_map" in functions else None),
        "task": _task_context(eqs, precision) if any(f in TASK_OUTPUTS for f in functions) else None,
        "contact": (_contact_context(eqs, precision) if any(f in CONTACT_SOLVED + EXTERNAL_OUTPUTS for f in functions)
                    else None),
        "header_only": header_only,
        "notes": [comment_text(note) for note in notes],
        "math_header": True,
        **_contract_context(eqs, precision, built),
        "status_list": _status_list(built, prefix),
        "size_target": "",
        "size_command": "",
        "size_doubles": "",
        "regressor_parameters": _regressor_parameters(eqs) if "regressor" in functions else [],
        "base_parameters": _base_parameters(eqs) if "base_regressor" in functions else [],
        "fuse_from": FUSE_FROM_STATEMENTS,
        "batch": batch,
        **_code_needs(built),
    }


def _code_needs(built) -> dict:
    """What the C of the functions ``built`` needs beside them in its file (the templates'
    context: the sin/cos blocks, the vector helpers, the fused multiply-add macros, float.h)."""
    return {
        "functions": built,
        "float_header": any(f.returns == "int" for f in built),
        "trig_double": any(f.trig_type == "double" for f in built) or any(
            f.batch and f.batch["lanes"] is not None and f.batch["trig"] for f in built),
        "vector_trig": any(f.batch and f.batch["lanes"] is not None and f.batch["trig"] for f in built),
        "trig_float": any(f.trig_type == "float" for f in built),
        "gram_vector": any(f.gram_loop for f in built),
        "fma_type": next((f.fma_type for f in built if f.fma_type), ""),
        "vector": any(f.batch and f.batch["lanes"] is not None for f in built),
        "vector_functions": sorted(set().union(*(f.batch["vector_functions"] for f in built if f.batch))),
    }


def _source_files(env, context: dict, built, prefix: str, file_bytes: int | None) -> dict[str, str]:
    """``{NAME_dynamics.c: text}``, or for C of more than ``file_bytes`` the functions in order in
    ``NAME_dynamics.c``, ``NAME_dynamics_2.c``, ... of at most about ``file_bytes`` each, every file
    with what its functions need (:func:`_code_needs`)."""
    template = env.get_template("dynamics.c.j2")
    whole = template.render(**context)
    if file_bytes is None or len(whole) <= file_bytes or len(built) < 2:
        return {f"{prefix}_dynamics.c": whole}
    groups, size = [[]], 0
    for f in built:
        alone = len(template.render(**{**context, **_code_needs([f])}))
        if groups[-1] and size + alone > file_bytes:
            groups.append([])
            size = 0
        groups[-1].append(f)
        size += alone
    return {f"{prefix}_dynamics{'' if k == 0 else f'_{k + 1}'}.c": template.render(**{**context, **_code_needs(group)})
            for k, group in enumerate(groups)}
