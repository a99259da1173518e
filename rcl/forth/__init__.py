"""The Forth machine: memory image, dictionary, inner and outer interpreter.

Read the modules in this order (jonesforth's order): memory, dictionary,
primitives, inner, control, decode, compiler (with compile_block and
compile_loops), numbers, outer, machine.
"""
