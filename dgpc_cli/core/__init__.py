"""Numerical core: the net's variable layout, the constraint terms and the solver."""
