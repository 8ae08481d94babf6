"""The step on several threads, bit for bit the serial step.

Holds: ``parallel`` (the contact pass by chunks, the block -> contact table), ``region`` (many
steps in one parallel region when gravity is the only other force), ``atomics`` (LLVM atomics
for numba). Compiled only for a model with ``threads > 1``.

May import: numpy, numba, ``dem_core.contact``, ``dem_core.step`` (state, integration,
relaxation), ``dem_core.components.gravity``.
"""
