"""How fast bench/fib.fs and bubble.fs could run in Python: floors under rcl.

    python3 bench/floor.py [--repeat K]
    pypy3 bench/floor.py [--repeat K]

fib.fs makes 1,483,760 Forth calls (16 x fib(23), each call of FIB one
Forth call through FIB-VECTOR @ EXECUTE). Any Forth that runs compiled
Python makes at least one Python call per Forth call, so plain Python
doing the same recursion is a floor no Forth in Python can go under. This
script times the same computation written directly in Python, in two
forms, on whichever interpreter runs it (best CPU time of K runs):

* bare: Python's own recursion on Python ints, masked to 16 bits:
  the call itself and nothing else.
* stacks: the same with the data stack and the return stack as Python
  lists, which a Forth cannot do without (words find their arguments on
  the data stack; R@, I and EXECUTE can look at the return stack).
  Still no virtual clock, no interrupt check, no memory behind
  FIB-VECTOR, no 64 KiB image and no DPL: everything rcl's FIB does on
  top of this is the price of running the 1986 board's Forth exactly.

bubble.fs is timed once more, as plain Python over a 64 KiB bytearray
(rcl's memory, which SEE, DUMP and every @ read, so a sort must go
through it) with Python's own `for` loops and no stack at all: the least
any Forth in Python can do for it.

Each prints the checksum bench/expected.txt gives for its program
(fib.fs 32528, bubble.fs 13585), so it computes what the Forth program
computes.
"""
import argparse
import time

from run import best_of          # bench/run.py

REPETITIONS, N = 16, 23


def fib_bare(n):
    if n < 2:
        return n
    return (fib_bare(n - 1) + fib_bare(n - 2)) & 0xFFFF


def bare():
    acc = 0
    for _ in range(REPETITIONS):
        acc = (acc + fib_bare(N)) & 32767
    return acc


def stacks():
    s, rs = [], []

    def fib():                         # ( n -- fib[n] )
        n = s.pop()
        s.append(n)                    # DUP 2 < IF EXIT THEN
        if (n ^ 0x8000) < (2 ^ 0x8000):
            return
        s.append((n - 1) & 0xFFFF)     # DUP 1 - FIB
        rs.append(1)
        fib()
        rs.pop()
        a = s.pop()                    # SWAP 2 - FIB
        n = s.pop()
        s.append(a)
        s.append((n - 2) & 0xFFFF)
        rs.append(2)
        fib()
        rs.pop()
        b = s.pop()                    # +
        s.append((s.pop() + b) & 0xFFFF)

    acc = 0
    for _ in range(REPETITIONS):
        s.append(N)
        fib()
        acc = (acc + s.pop()) & 32767
    return acc


def bubble():
    mem, base, n = bytearray(65536), 0x2000, 200

    def item(i):
        a = base + 2 * i
        return mem[a] | mem[a + 1] << 8

    def greater(a):                    # the cell at a > the next, signed
        return ((mem[a] | mem[a + 1] << 8) ^ 0x8000) > \
            ((mem[a + 2] | mem[a + 3] << 8) ^ 0x8000)

    seed, acc = 1, 0
    for _ in range(50):
        for a in range(base, base + 2 * n, 2):         # FILL-ITEMS
            seed = (seed * 25173 + 13849) & 32767
            mem[a], mem[a + 1] = seed & 0xFF, seed >> 8
        for i in range(1, n):                          # SORT
            for a in range(base, base + 2 * (n - i), 2):
                x = mem[a] | mem[a + 1] << 8
                y = mem[a + 2] | mem[a + 3] << 8
                if (x ^ 0x8000) > (y ^ 0x8000):
                    mem[a], mem[a + 1] = y & 0xFF, y >> 8
                    mem[a + 2], mem[a + 3] = x & 0xFF, x >> 8
        ok = 0 if any(greater(a) for a in range(base, base + 2 * (n - 1), 2)) else 0xFFFF
        acc = (acc + item(0) + item(n // 2) + item(n - 1) + ok) & 32767   # CHECK
    return acc


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('--repeat', type=int, default=5, metavar='K',
                    help='best of K runs (default 5)')
    args = ap.parse_args()
    print('| in plain Python | CPU s | checksum |')
    print('|---|---:|---:|')
    for name, run in (('fib.fs, bare recursion', bare),
                      ('fib.fs, with data and return stacks', stacks),
                      ('bubble.fs, over a 64 KiB bytearray', bubble)):
        seconds, checksum = best_of(args.repeat, run, time.process_time)
        print(f'| {name} | {seconds:.3f} | {checksum} |')


if __name__ == '__main__':
    main()
