"""Compile generated C with the system compiler and call it through ctypes (for ``verify``,
tests and benchmarks)."""

from __future__ import annotations

import ctypes
import dataclasses
import os
import shutil
import subprocess
import tempfile

import numpy as np

from ..model.errors import SymdynError
from ..model.outputs import COMBINED, COMBINED_SPECS, REGISTRY, SPECS, Dimensions, returns_status

WARNING_FLAGS = ["-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror"]


def find_compiler() -> str:
    for name in (os.environ.get("CC"), "cc", "gcc", "clang"):
        if name and shutil.which(name):
            return name
    raise SymdynError("no C compiler found (set CC or install gcc)")


#: the optimization level :func:`compile_shared` uses: -O2, what users build with, unless the
#: environment variable ``SYMDYN_CHECK_OPTIMIZATION`` names another (-O0 to -O3, -Os).  The test
#: suite sets -O1 (tests/conftest.py): its numerical checks read the same IEEE results, and its
#: biggest libraries compile about 40% faster (Solo-12's contact functions, 8 MB of C: 38.5 ->
#: 24.0 s); the builds that check -O2's and -O3's warnings name their flags, and `symdyn verify`
#: and `symdyn fuzz` (.ci/run's campaign) run at -O2
OPTIMIZATION_VARIABLE = "SYMDYN_CHECK_OPTIMIZATION"


def optimization_flag() -> str:
    """The -O flag of :func:`compile_shared` (:data:`OPTIMIZATION_VARIABLE`, else -O2)."""
    chosen = os.environ.get(OPTIMIZATION_VARIABLE, "")
    return chosen if chosen in ("-O0", "-O1", "-O2", "-O3", "-Os") else "-O2"


def compile_shared(c_file, out_dir: str, extra_flags=()) -> str:
    """Compile ``c_file`` (a path, or a list of paths: one library of them all, named after the
    first) into a shared library in ``out_dir`` (strict warnings as errors; at
    :func:`optimization_flag`, unless ``extra_flags`` name another)."""
    sources = [c_file] if isinstance(c_file, str) else list(c_file)
    lib = os.path.join(out_dir, os.path.splitext(os.path.basename(sources[0]))[0] + ".so")
    cmd = [find_compiler(), *WARNING_FLAGS, optimization_flag(), "-fPIC", "-shared", *sources, "-o", lib, "-lm",
           *extra_flags]
    result = subprocess.run(cmd, capture_output=True, text=True)
    if result.returncode != 0:
        raise SymdynError(f"compiling {c_file} failed: {result.stderr.strip()[:2000]}")
    return lib


class CompiledDynamics:
    """ctypes access to a compiled ``NAME_dynamics`` library; methods mirror
    :class:`symdyn.derive.numeric.NumericEquations` (numpy in, numpy out).  ``dims``: the sizes
    of its outputs (:meth:`Dimensions.of` the robot; an int is a chain of that many actuated
    joints, the pose task and no frames); ``n_params``: its runtime parameters (``p``)."""

    def __init__(self, library: str, prefix: str, dims: Dimensions | int, n_params: int, precision: str = "double"):
        self.lib = ctypes.CDLL(library)
        self.dims = dims if isinstance(dims, Dimensions) else Dimensions(dims)
        self.prefix, self.n, self.np = prefix, self.dims.dof, n_params
        single = precision in ("float", "mixed")
        self.ctype = ctypes.c_float if single else ctypes.c_double
        self.dtype = np.float32 if single else np.float64

    def _call(self, name, args, p, out_size, out=None, status=False):
        fn = getattr(self.lib, f"{self.prefix}_{name}")
        arrays = [np.ascontiguousarray(a, dtype=self.dtype) for a in args]
        if self.np:
            arrays.append(np.ascontiguousarray(p, dtype=self.dtype))
        out = np.zeros(out_size, dtype=self.dtype) if out is None else np.ascontiguousarray(out, dtype=self.dtype)
        pointer = ctypes.POINTER(self.ctype)
        fn.restype = ctypes.c_int if status else None
        code = fn(*[a.ctypes.data_as(pointer) for a in arrays], out.ctypes.data_as(pointer))
        return (int(code), out) if status else out

    def _call_outputs(self, name, args, p, sizes, status=False, fill=0.0):
        """Call ``NAME_<name>`` that writes several output arrays (of ``sizes`` numbers each,
        filled with ``fill`` before the call) after its inputs; returns them, flat (``status``:
        the function returns an int, and the result is ``(status, outputs)``)."""
        fn = getattr(self.lib, f"{self.prefix}_{name}")
        arrays = [np.ascontiguousarray(a, dtype=self.dtype) for a in args]
        if self.np:
            arrays.append(np.ascontiguousarray(p, dtype=self.dtype))
        outputs = [np.full(size, fill, dtype=self.dtype) for size in sizes]
        pointer = ctypes.POINTER(self.ctype)
        fn.restype = ctypes.c_int if status else None
        code = fn(*[a.ctypes.data_as(pointer) for a in arrays + outputs])
        return (int(code), outputs) if status else outputs

    def _outputs_of(self, name, parts, args, p, sizes):
        """The flat outputs of ``NAME_<name>`` (writing ``parts``): a function that returns a
        status (task space, the inverse mass matrix, the forward-dynamics derivatives) writes
        nothing on a nonzero one, so its outputs start as NaN (never silent zeros)."""
        if returns_status(name):
            return self._call_outputs(name, args, p, sizes, status=True, fill=float("nan"))[1]
        return self._call_outputs(name, args, p, sizes)

    def with_status(self, name, *args, p=None, fill=float("nan")):
        """``(status, outputs)`` of a function that returns a status (a task-space function, or
        ``forward_dynamics_checked``): ``outputs`` a tuple of numpy arrays shaped as the outputs
        (a vector for one column), each filled with ``fill`` before the call, so that entries the
        function did not write keep it."""
        parts = COMBINED.get(name, (name.removesuffix("_checked"),))
        dims = self.dims
        specs = [REGISTRY[part] for part in parts]
        blocks = [(spec, shape) for spec in specs for _, shape in spec.argument_shapes(dims)]
        code, flat = self._call_outputs(name, args, p, [r * c for _, (r, c) in blocks], status=True, fill=fill)
        return code, tuple(f if spec.is_vector else f.reshape(shape) for f, (spec, shape) in zip(flat, blocks))

    def forward_dynamics_checked(self, q, qd, tau, p=None, qdd=None):
        """``(status, qdd)`` from ``NAME_forward_dynamics_checked``; ``qdd`` (default zeros) is the
        array passed in, returned as the function left it."""
        return self._call("forward_dynamics_checked", (q, qd, tau), p, self.n, out=qdd, status=True)


def _compiled_method(spec):
    """``CompiledDynamics.<output>(*inputs, p=None)``: calls ``NAME_<output>`` and returns the
    output as numpy (a vector for one column, else the matrix; split arguments side by side)."""
    def method(self, *args, p=None, columns: int | None = None):
        if len(args) == len(spec.inputs) + 1 and p is None:
            *args, p = args
        dims = self.dims if columns is None else dataclasses.replace(self.dims, base_parameters=columns)
        shape = spec.shape(dims)
        if 0 in shape and spec.name == "base_regressor":
            raise ValueError("base_regressor: give the number of base parameters (columns, or in the library's "
                             "Dimensions)")
        blocks = spec.argument_shapes(dims)
        flat = self._outputs_of(spec.name, (spec.name,), args, p, [rows * cols for _, (rows, cols) in blocks])
        if len(blocks) > 1:
            return np.hstack([f.reshape(rows, cols) for f, (_, (rows, cols)) in zip(flat, blocks)])
        return flat[0] if spec.is_vector else flat[0].reshape(shape)
    method.__name__ = spec.name
    method.__doc__ = f"{spec.summary} From ``NAME_{spec.name}``; shape {spec.shape_text}."
    return method


def _combined_method(combined):
    """``CompiledDynamics.<combined>(*inputs, p=None)``: the tuple of its parts' outputs."""
    parts = [REGISTRY[part] for part in combined.parts]

    def method(self, *args, p=None):
        if len(args) == len(combined.inputs) + 1 and p is None:
            *args, p = args
        dims = self.dims
        flat = self._outputs_of(combined.name, combined.parts, args, p,
                                [r * c for part in parts for _, (r, c) in part.argument_shapes(dims)])
        return tuple(f if part.is_vector else f.reshape(part.shape(dims)) for f, part in zip(flat, parts))
    method.__name__ = combined.name
    method.__doc__ = f"{combined.summary} From ``NAME_{combined.name}``: ({', '.join(combined.parts)})."
    return method


for _spec in SPECS:
    setattr(CompiledDynamics, _spec.name, _compiled_method(_spec))
for _combined in COMBINED_SPECS:
    setattr(CompiledDynamics, _combined.name, _combined_method(_combined))


def build_and_load(files: dict[str, str], prefix: str, dims: Dimensions | int, n_params: int,
                   precision: str = "double", workdir: str | None = None, extra_flags=()) -> CompiledDynamics:
    """Write generated ``files`` to ``workdir`` (a new temporary directory by default), compile
    (``extra_flags`` after the defaults) and load; ``dims``: the sizes of the outputs
    (:meth:`Dimensions.of` the robot, or ``eqs.dimensions``)."""
    workdir = workdir or tempfile.mkdtemp(prefix="symdyn_")
    for name, text in files.items():
        with open(os.path.join(workdir, name), "w") as handle:
            handle.write(text)
    lib = compile_shared([os.path.join(workdir, name) for name in c_sources(files, prefix)], workdir, extra_flags)
    return CompiledDynamics(lib, prefix, dims, n_params, precision)


def c_sources(files, prefix: str) -> list[str]:
    """The C files among generated ``files`` (names), ``NAME_dynamics.c`` first, then the others
    of C written as several files (``NAME_dynamics_2.c``, ...: symdyn.emit.cgen.C_FILE_BYTES) in order."""
    others = sorted((name for name in files if name.startswith(f"{prefix}_dynamics_") and name.endswith(".c")
                     and name[len(prefix) + 10:-2].isdigit()), key=lambda name: int(name[len(prefix) + 10:-2]))
    return [f"{prefix}_dynamics.c", *others]


__all__ = ["compile_shared", "c_sources", "build_and_load", "CompiledDynamics", "find_compiler"]


class CompiledPlatform:
    """ctypes access to a compiled platform robot (:mod:`symdyn.emit.parallel_c`): one method per
    generated function, numpy arrays in, ``(status, outputs...)`` out (outputs as numpy arrays;
    zeros when the status is nonzero)."""

    def __init__(self, library: str, prefix: str, precision: str = "double"):
        from ..derive.parallel import FUNCTIONS, INPUT_SIZES
        self.lib = ctypes.CDLL(library)
        self.prefix = prefix
        self.ctype = ctypes.c_float if precision == "float" else ctypes.c_double
        self.dtype = np.float32 if precision == "float" else np.float64
        self._sizes = INPUT_SIZES
        self._functions = FUNCTIONS

    def __getattr__(self, name):
        if name.startswith("_") or name not in self._functions:
            raise AttributeError(name)
        inputs, outputs, _ = self._functions[name]
        fn = getattr(self.lib, f"{self.prefix}_{name}")
        fn.restype = ctypes.c_int

        def call(*args):
            if len(args) != len(inputs):
                raise TypeError(f"{name} takes {', '.join(inputs)}")
            arrays = [np.ascontiguousarray(np.asarray(a, dtype=self.dtype).reshape(self._sizes[k]))
                      for k, a in zip(inputs, args)]
            outs = [np.zeros(rows * cols, dtype=self.dtype) for _, rows, cols in outputs]
            pointer = ctypes.POINTER(self.ctype)
            status = fn(*[a.ctypes.data_as(pointer) for a in arrays], *[o.ctypes.data_as(pointer) for o in outs])
            shaped = [o.reshape(rows, cols) if cols > 1 else o for o, (_, rows, cols) in zip(outs, outputs)]
            return (status, *shaped)
        return call


def build_platform(files: dict[str, str], prefix: str, precision: str = "double", workdir: str | None = None,
                   extra_flags=()) -> CompiledPlatform:
    """Write a platform robot's generated files to ``workdir`` (default: a new temporary
    directory), compile them (strict warnings as errors) and load the library."""
    workdir = workdir or tempfile.mkdtemp(prefix="symdyn-platform-")
    for name, text in files.items():
        with open(os.path.join(workdir, name), "w", encoding="utf-8") as handle:
            handle.write(text)
    library = compile_shared(os.path.join(workdir, f"{prefix}_dynamics.c"), workdir, extra_flags)
    return CompiledPlatform(library, prefix, precision)
