"""Quieting C libraries that write to the process's standard error themselves (urdfdom when
Pinocchio parses a URDF, MuJoCo's compiler warnings): their lines would break symdyn's
one-line messages."""

from __future__ import annotations

import os
import sys


class stderr_silenced:
    """Point file descriptor 2 at the null device for a while."""

    def __enter__(self):
        sys.stderr.flush()
        self.saved = os.dup(2)
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, 2)
        os.close(devnull)
        return self

    def __exit__(self, *exc):
        os.dup2(self.saved, 2)
        os.close(self.saved)
        return False
