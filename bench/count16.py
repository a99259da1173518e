"""Count the Forth words a benchmark executes, on a 16-bit F83-style model.

    python3 bench/count16.py bench/fib.fs [--here ADDR]

A deliberately tiny, slow, stand-alone interpreter for just the words the
benchmarks use.  It exists for two checks that gforth cannot make:

* the checksum on 16-bit cells (F83 rules: arithmetic mod 2^16, floored
  division, F83's DO ... LOOP that ends when the index crosses limit-1/limit)
  must equal gforth's on 64-bit cells;
* the number of executed words, for the `\\ WORDS-EXECUTED` comment.

What counts as one executed word (what F83 would thread through NEXT): every
compiled token -- a primitive, a literal, a call to a colon word, a CONSTANT
or VARIABLE, `;` (EXIT), IF/WHILE/UNTIL (?BRANCH), ELSE/REPEAT (BRANCH),
DO (DO), LOOP (LOOP), +LOOP (+LOOP), ." (.") -- and every word or number
interpreted at top level.  BEGIN and THEN compile nothing and count nothing.
`--here` sets where the dictionary data starts (default 0x7F00 so that the
arrays straddle address 32768, as they might in a 64 KiB F83 image).
"""
import sys
import time

M = 0xFFFF


def signed(v):
    return v - 0x10000 if v & 0x8000 else v


class Forth16:
    def __init__(self, here=0x7F00):
        self.mem = bytearray(0x10000)
        self.here = here
        self.s = []          # data stack, cells as 0..65535
        self.r = []          # return stack: (code, ip) frames and loop cells
        self.out = []
        self.count = 0
        self.words = {}      # NAME -> (kind, value, immediate)
        self.xts = []        # execution tokens are indexes into this list
        self.compiling = None
        self.ctrl = []       # compile-time control-flow stack
        for name in PRIMS:
            self.define(name, 'prim', PRIMS[name])

    # -- dictionary ---------------------------------------------------------
    def define(self, name, kind, value):
        self.xts.append((kind, value))
        self.words[name.upper()] = len(self.xts) - 1

    def cell(self, a):
        return self.mem[a] | self.mem[(a + 1) & M] << 8

    def store(self, a, v):
        self.mem[a] = v & 0xFF
        self.mem[(a + 1) & M] = (v >> 8) & 0xFF

    # -- inner interpreter ---------------------------------------------------
    def execute(self, xt):
        kind, value = self.xts[xt]
        self.count += 1
        if kind == 'prim':
            value(self)
        elif kind == 'const':
            self.s.append(value)
        elif kind == 'colon':
            self.run(value)

    def run(self, code):
        ip = 0
        while True:
            op, arg = code[ip]
            ip += 1
            if op == 'call':
                kind, value = self.xts[arg]
                self.count += 1
                if kind == 'colon':
                    self.r.append((code, ip))
                    code, ip = value, 0
                elif kind == 'prim':
                    value(self)
                else:
                    self.s.append(value)
                continue
            self.count += 1
            if op == 'lit':
                self.s.append(arg)
            elif op == 'exit':
                if not self.r or not isinstance(self.r[-1], tuple):
                    return
                code, ip = self.r.pop()
            elif op == '?branch':
                if self.s.pop() == 0:
                    ip = arg
            elif op == 'branch':
                ip = arg
            elif op == 'do':                       # F83: limit' index'
                start, limit = self.s.pop(), self.s.pop()
                lim = (limit + 0x8000) & M
                self.r.append(lim)
                self.r.append((start - lim) & M)
            elif op in ('loop', '+loop'):
                n = 1 if op == 'loop' else signed(self.s.pop())
                new = signed(self.r[-1]) + n
                if -0x8000 <= new <= 0x7FFF:       # no overflow: go on
                    self.r[-1] = new & M
                    ip = arg
                else:
                    del self.r[-2:]
            elif op == 'type':
                self.out.append(arg)
            elif op == 'execute':                  # jumps into the word: the
                kind, value = self.xts[self.s.pop()]   # word is not a 2nd count
                if kind == 'colon':
                    self.r.append((code, ip))
                    code, ip = value, 0
                elif kind == 'prim':
                    value(self)
                else:
                    self.s.append(value)

    # -- outer interpreter ---------------------------------------------------
    def evaluate(self, text):
        for line in text.splitlines():
            self.line, self.pos = line, 0
            while True:
                tok = self.token()
                if tok is None:
                    break
                self.interpret(tok)
        return ''.join(self.out)

    def token(self, delim=None):
        line, p = self.line, self.pos
        if delim:                                  # skip one blank, then text
            end = line.find(delim, p)
            end = len(line) if end < 0 else end
            self.pos = end + 1
            return line[p:end]
        while p < len(line) and line[p].isspace():
            p += 1
        if p >= len(line):
            self.pos = p
            return None
        q = p
        while q < len(line) and not line[q].isspace():
            q += 1
        self.pos = q + 1
        return line[p:q].upper()

    def interpret(self, tok):
        if tok in IMMEDIATE:
            IMMEDIATE[tok](self)
            return
        if tok in DEFINING and self.compiling is None:
            DEFINING[tok](self)
            return
        if tok in self.words:
            xt = self.words[tok]
            if self.compiling is not None:
                if self.xts[xt][1] is PRIMS['EXECUTE']:
                    self.compiling.append(('execute', None))
                else:
                    self.compiling.append(('call', xt))
            else:
                self.execute(xt)
            return
        n = int(tok) & M                           # a number (decimal only)
        if self.compiling is not None:
            self.compiling.append(('lit', n))
        else:
            self.count += 1
            self.s.append(n)


# -- primitives --------------------------------------------------------------
def binop(f):
    def prim(vm):
        b, a = vm.s.pop(), vm.s.pop()
        vm.s.append(f(a, b) & M)
    return prim


def floored(a, b, want):
    a, b = signed(a), signed(b)
    if b == 0:                                     # F83: 7 0 / = 0, 7 0 MOD = 7
        return 0 if want == 'q' else a
    return a // b if want == 'q' else a % b


def flag(x):
    return M if x else 0


def dot(vm, unsigned=False):
    v = vm.s.pop()
    vm.out.append(f"{v if unsigned else signed(v)} ")


def here_allot(vm):
    vm.here = (vm.here + signed(vm.s.pop())) & M


def comma(vm):
    vm.store(vm.here, vm.s.pop())
    vm.here = (vm.here + 2) & M


def loop_index(vm, depth):
    return (vm.r[-1 - depth] + vm.r[-2 - depth]) & M


def c_store(vm):
    a, v = vm.s.pop(), vm.s.pop()
    vm.mem[a] = v & 0xFF


def store(vm):
    a, v = vm.s.pop(), vm.s.pop()
    vm.store(a, v)


PRIMS = {
    '+': binop(lambda a, b: a + b),
    '-': binop(lambda a, b: a - b),
    '*': binop(lambda a, b: a * b),
    '/': binop(lambda a, b: floored(a, b, 'q')),
    'MOD': binop(lambda a, b: floored(a, b, 'r')),
    'AND': binop(lambda a, b: a & b),
    'OR': binop(lambda a, b: a | b),
    '=': binop(lambda a, b: flag(a == b)),
    '<': binop(lambda a, b: flag(signed(a) < signed(b))),
    '>': binop(lambda a, b: flag(signed(a) > signed(b))),
    '0=': lambda vm: vm.s.append(flag(vm.s.pop() == 0)),
    'DUP': lambda vm: vm.s.append(vm.s[-1]),
    'DROP': lambda vm: vm.s.pop(),
    'SWAP': lambda vm: vm.s.append(vm.s.pop(-2)),
    'OVER': lambda vm: vm.s.append(vm.s[-2]),
    'ROT': lambda vm: vm.s.append(vm.s.pop(-3)),
    '2DUP': lambda vm: vm.s.extend(vm.s[-2:]),
    '2DROP': lambda vm: vm.s.__delitem__(slice(-2, None)),
    '@': lambda vm: vm.s.append(vm.cell(vm.s.pop())),
    '!': store,
    'C@': lambda vm: vm.s.append(vm.mem[vm.s.pop()]),
    'C!': c_store,
    'I': lambda vm: vm.s.append(loop_index(vm, 0)),
    'J': lambda vm: vm.s.append(loop_index(vm, 2)),
    'EXECUTE': lambda vm: vm.execute(vm.s.pop()),
    'HERE': lambda vm: vm.s.append(vm.here),
    'ALLOT': here_allot,
    ',': comma,
    '.': dot,
    'U.': lambda vm: dot(vm, True),
    'CR': lambda vm: vm.out.append('\n'),
}


# -- compiling and defining words -----------------------------------------------
def colon(vm):
    vm.name = vm.token()
    vm.compiling = []


def semicolon(vm):
    vm.compiling.append(('exit', None))
    vm.define(vm.name, 'colon', vm.compiling)
    vm.compiling = None


def create(vm):
    vm.define(vm.token(), 'const', vm.here)


def variable(vm):
    create(vm)
    vm.store(vm.here, 0)
    vm.here += 2


def constant(vm):
    vm.define(vm.token(), 'const', vm.s.pop())


def tick(vm):
    vm.count += 1
    vm.s.append(vm.words[vm.token()])


def mark(vm, op):                      # compile op with a blank target
    vm.compiling.append([op, None])
    return len(vm.compiling) - 1


def resolve(vm, at, target=None):
    vm.compiling[at] = (vm.compiling[at][0],
                        len(vm.compiling) if target is None else target)


def c_if(vm):
    vm.ctrl.append(mark(vm, '?branch'))


def c_else(vm):
    at = mark(vm, 'branch')
    resolve(vm, vm.ctrl.pop())
    vm.ctrl.append(at)


def c_then(vm):
    resolve(vm, vm.ctrl.pop())


def c_begin(vm):
    vm.ctrl.append(len(vm.compiling))


def c_while(vm):
    vm.ctrl.append(mark(vm, '?branch'))


def c_repeat(vm):
    w, b = vm.ctrl.pop(), vm.ctrl.pop()
    vm.compiling.append(('branch', b))
    resolve(vm, w)


def c_until(vm):
    vm.compiling.append(('?branch', vm.ctrl.pop()))


def c_do(vm):
    vm.compiling.append(('do', None))
    vm.ctrl.append(len(vm.compiling))


def c_loop(op):
    return lambda vm: vm.compiling.append((op, vm.ctrl.pop()))


def c_dotquote(vm):
    vm.compiling.append(('type', vm.token('"')))


def c_exit(vm):
    vm.compiling.append(('exit', None))


IMMEDIATE = {
    '\\': lambda vm: setattr(vm, 'pos', len(vm.line)),
    '(': lambda vm: vm.token(')'),
    ';': semicolon, 'IF': c_if, 'ELSE': c_else, 'THEN': c_then,
    'BEGIN': c_begin, 'WHILE': c_while, 'REPEAT': c_repeat,
    'UNTIL': c_until, 'DO': c_do, 'LOOP': c_loop('loop'),
    '+LOOP': c_loop('+loop'), '."': c_dotquote, 'EXIT': c_exit,
}
DEFINING = {':': colon, 'CREATE': create, 'VARIABLE': variable,
            'CONSTANT': constant, "'": tick}


def main(argv):
    here = 0x7F00
    if '--here' in argv:
        here = int(argv[argv.index('--here') + 1], 0)
    for path in [a for a in argv if a.endswith('.fs')]:
        vm = Forth16(here)
        t0 = time.perf_counter()
        out = vm.evaluate(open(path).read())
        dt = time.perf_counter() - t0
        checksum = [l for l in out.splitlines() if l.startswith('CHECKSUM')]
        print(f"{path}: {' '.join(checksum)!s:20} words {vm.count:,} "
              f"in {dt:.1f} s ({vm.count / dt / 1e6:.2f} M words/s) "
              f"stack {vm.s}")


if __name__ == '__main__':
    main(sys.argv[1:])
