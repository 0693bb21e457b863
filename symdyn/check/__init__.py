"""Checking and timing what symdyn produces: the matching Pinocchio model, the independent
50-digit mpmath reference, compiling generated C, timing harnesses and ``symdyn bench``.
"""
