"""Vocabularies and the search order (F83's ONLY ALSO, Forth 2012's
Search-Order words). ONLY, ALSO, FORTH, DEFINITIONS, ORDER and
friends live in ROOT too, so `ONLY FORTH ALSO DEFINITIONS` always works."""
from rcl.errors import ForthError
from rcl.forth import inner
from rcl.forth.dictionary import ORDER_MAX
from rcl.forth.memory import MASK
from rcl.forth.primitives import prim
from rcl.words.compiling import parse_word


def voc_name(m, wid):
    """The name of the vocabulary whose word list is wid."""
    name = m.dictionary.name_of((wid - 2) & MASK)
    return name if name and m.memory.fetch((wid - 2) & MASK) == inner.N["(DOVOC)"] \
        else "%04X" % wid


@prim("VOCABULARY", "( -- ) a named word list; running it puts it first in the order")
def vocabulary(m):
    m.dictionary.create(parse_word(m), inner.N["(DOVOC)"])
    m.dictionary.new_wordlist()


@prim("WORDLIST", "( -- wid ) a new, empty word list")
def wordlist(m):
    m.s.append(m.dictionary.new_wordlist())


@prim("ONLY", "( -- ) search ROOT only", wordlist="ROOT")
def only(m):
    m.dictionary.set_order([m.root_wid, m.root_wid])


@prim("ALSO", "( -- ) duplicate the first vocabulary of the order", wordlist="ROOT")
def also(m):
    order = m.dictionary.order()
    if len(order) >= ORDER_MAX:
        raise ForthError(-49, "Search order overflow")
    m.dictionary.set_order(order[:1] + order)


@prim("PREVIOUS", "( -- ) drop the first vocabulary of the order", wordlist="ROOT")
def previous(m):
    order = m.dictionary.order()
    if not order:
        raise ForthError(-50, "Search order underflow")
    m.dictionary.set_order(order[1:])


@prim("DEFINITIONS", "( -- ) new words go into the first vocabulary of the order",
      wordlist="ROOT")
def definitions(m):
    order = m.dictionary.order()
    if order:
        m.memory.store(m.a_current, order[0])


@prim("ORDER", "( -- ) show the search order and CURRENT", wordlist="ROOT")
def order(m):
    names = " ".join(voc_name(m, w) for w in m.dictionary.order())
    m.type("Context: %s  Current: %s " % (names, voc_name(m, m.memory.fetch(m.a_current))))


@prim("FORTH-WORDLIST", "( -- wid )", wordlist="ROOT")
def forth_wordlist(m):
    m.s.append(m.forth_wid)


@prim("GET-ORDER", "( -- wid_n ... wid_1 n )", wordlist="ROOT")
def get_order(m):
    order = m.dictionary.order()
    m.s.extend(reversed(order))
    m.s.append(len(order))


@prim("SET-ORDER", "( wid_n ... wid_1 n -- ) -1 means the minimum order", wordlist="ROOT")
def set_order(m):
    n = m.s.pop()
    if n == MASK:
        only(m)
        return
    m.dictionary.set_order([m.s.pop() for _ in range(n)])


@prim("GET-CURRENT", "( -- wid )")
def get_current(m):
    m.s.append(m.memory.fetch(m.a_current))


@prim("SET-CURRENT", "( wid -- )")
def set_current(m):
    m.memory.store(m.a_current, m.dictionary.check_wid(m.s.pop()))


@prim("SEARCH-WORDLIST", "( addr u wid -- 0 | xt 1 | xt -1 )")
def search_wordlist(m):
    wid, u, a = m.s.pop(), m.s.pop(), m.s.pop()
    lfa = m.dictionary.find_in(m.dictionary.check_wid(wid), m.memory.text(a, u)) if u else 0
    if not lfa:
        m.s.append(0)
    else:
        imm = m.dictionary.flags(lfa) & 0x40
        m.s.extend(((lfa + 2) & MASK, 1 if imm else MASK))


@prim("VOCS", "( -- ) list every vocabulary", wordlist="ROOT")
def vocs(m):
    m.type(" ".join(voc_name(m, w) for w in m.dictionary.wordlists()) + " ")
