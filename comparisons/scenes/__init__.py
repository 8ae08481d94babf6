"""Thesis scenes as data: geometry, materials and boundary conditions, one module per case."""
