"""Bit-true model of the finequad RTL: one module per RTL module, named as it (sim/README.md)."""
