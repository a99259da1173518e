"""The Forth machine: memory image, dictionary, inner and outer interpreter.

Read the modules in this order (jonesforth's order): memory, header,
primitives, inner, compiler, numbers, outer, machine.
"""
