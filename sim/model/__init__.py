"""Bit-true model of the finequad RTL: one module per RTL block (see README)."""
