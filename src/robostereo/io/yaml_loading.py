"""YAML text read into plain values with bounded work: the loader every input file uses.

:func:`load_yaml` is :func:`yaml.safe_load` with the failures a hand-edited or hostile
file can cause turned into one-line :class:`~robostereo.errors.InputError` s naming the
file: invalid YAML, an integer of more digits than Python converts, nesting deeper than
Python's recursion, and aliases that expand to more than :data:`MAX_ALIAS_NODES` nodes
(an "alias bomb": nine levels of nine aliases are 387 million nodes in a file of a few
hundred bytes, and every check that walks or prints such a value does that work).
"""

from __future__ import annotations

from typing import Any

import yaml

from robostereo.errors import InputError

__all__ = ["MAX_ALIAS_NODES", "load_yaml"]

MAX_ALIAS_NODES = 100_000
"""Most YAML nodes that aliases (``*name``) may add to a file's values when expanded.

A capture of 1000 views written out with a 4 x 4 matrix each is some 30,000 nodes, and a
file without aliases is not limited (its size bounds it); aliases that add more than
100,000 nodes are not a way of writing capture settings."""


class _LimitError(yaml.YAMLError):
    """Aliases that are recursive or expand too far."""


class _BoundedLoader(yaml.SafeLoader):
    """:class:`yaml.SafeLoader` that refuses documents whose aliases expand too far."""

    def compose_document(self) -> Any:
        node = super().compose_document()
        _check_aliases(node)
        return node


def _children(node: yaml.Node) -> list[yaml.Node]:
    if isinstance(node, yaml.SequenceNode):
        return list(node.value)
    if isinstance(node, yaml.MappingNode):
        return [n for pair in node.value for n in pair]
    return []


def _check_aliases(root: yaml.Node | None) -> None:
    """Raise :class:`_LimitError` when the aliases under `root` are recursive or expand
    to more than :data:`MAX_ALIAS_NODES` nodes beyond the document's own.

    Counts the expanded tree bottom-up, each distinct node once (memoised on identity),
    so the work is that of the document as written, not as expanded.
    """
    if root is None:
        return
    size: dict[int, int] = {}
    distinct = 0
    stack: list[tuple[yaml.Node, bool]] = [(root, False)]
    open_: set[int] = set()
    while stack:
        node, done = stack.pop()
        key = id(node)
        if done:
            open_.discard(key)
            size[key] = 1 + sum(size[id(c)] for c in _children(node))
            distinct += 1
            if size[key] - distinct > MAX_ALIAS_NODES:
                raise _LimitError(f"aliases expand to more than {MAX_ALIAS_NODES:,} "
                                     "values: an alias bomb?")
            continue
        if key in size:
            continue
        if key in open_:
            raise _LimitError("a recursive alias: a value that contains itself")
        open_.add(key)
        stack.append((node, True))
        stack.extend((c, False) for c in _children(node) if id(c) not in size)


def load_yaml(text: str, source: str) -> Any:
    """The plain values of one YAML document, with the work of reading it bounded.

    Parameters
    ----------
    text : str
        The file's text.
    source : str
        The file, for the message.

    Returns
    -------
    Any
        What :func:`yaml.safe_load` returns (mappings, lists, strings, numbers, None).

    Raises
    ------
    yaml.YAMLError
        Invalid YAML, as :func:`yaml.safe_load` raises it (each reader words its own
        message).
    InputError
        ``{source}: not a readable YAML file (...)``: recursive aliases or aliases
        expanding to more than :data:`MAX_ALIAS_NODES` nodes, an integer longer than
        Python converts, lists or mappings nested too deep.

    Examples
    --------
    >>> load_yaml("a: [1, 2]", "a.yaml")
    {'a': [1, 2]}
    >>> load_yaml("a: &a [1, 2]\\nb: [*a, *a]", "a.yaml")
    {'a': [1, 2], 'b': [[1, 2], [1, 2]]}
    >>> bomb = "a0: &a0 [x, x, x, x, x, x, x, x, x]\\n" + "".join(
    ...     f"a{i}: &a{i} [{', '.join([f'*a{i - 1}'] * 9)}]\\n" for i in range(1, 9))
    >>> load_yaml(bomb, "capture.yaml")
    Traceback (most recent call last):
    ...
    robostereo.errors.InputError: capture.yaml: not a readable YAML file (aliases expand ...
    """
    try:
        return yaml.load(text, Loader=_BoundedLoader)  # a SafeLoader
    except _LimitError as exc:
        raise InputError(f"{source}: not a readable YAML file ({exc})") from None
    except ValueError as exc:  # int() of more digits than sys.get_int_max_str_digits()
        raise InputError(f"{source}: not a readable YAML file (a number too long to "
                         f"read: {str(exc).split(':')[0]})") from None
    except RecursionError:
        raise InputError(f"{source}: not a readable YAML file (lists or mappings nested "
                         "too deep)") from None
