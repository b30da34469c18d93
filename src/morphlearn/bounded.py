"""Reading a file a user hands over (a config, a scenario or morphology file, a bundle's manifest, a
provenance record) with limits: a size, a nesting depth, and for YAML no alias that refers to the
collection holding it nor one that expands to millions of values. Without them ``/dev/zero`` was
read until the machine ran out of memory, and a deeply nested or self-referring file ended in a
RecursionError traceback (issue 38). Every refusal is a ValueError with one line that does not
name the file (the caller does: ``config.yaml_mapping`` and :func:`json_file`'s callers)."""

from __future__ import annotations

import json
import os
import stat
from pathlib import Path
from typing import Any

import yaml

#: The largest file read (a bundle's manifest is under 0.1 MB, a config a few kB).
MAX_BYTES = 10 * 2**20
#: The deepest nesting of mappings and lists (the configs nest 3 deep, a manifest 4).
MAX_DEPTH = 100
#: The most values a YAML file may expand to through its aliases (a "billion laughs" file).
MAX_VALUES = 1_000_000


def read_bytes(path: str | Path) -> bytes:
    """The bytes of a regular file of at most :data:`MAX_BYTES`. A device (``/dev/zero``) or a
    FIFO is refused before anything is read: it would never end, or block on its writer."""
    try:
        # O_NONBLOCK: opening a FIFO does not wait for a writer (no effect on a regular file)
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
    except OSError as e:
        raise ValueError(f"cannot read ({e.strerror})") from None
    except ValueError:  # os.open's own refusal: a NUL byte in the name
        raise ValueError("cannot read (its name holds a NUL byte)") from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            kind = "a folder" if stat.S_ISDIR(st.st_mode) else "a device, pipe or socket"
            raise ValueError(f"is {kind}, not a regular file; allowed: a file of at most {_size(MAX_BYTES)}")
        chunks, size = [], 0
        while size <= MAX_BYTES:  # a file that grows while read is cut here, not followed
            chunk = os.read(fd, MAX_BYTES + 1 - size)
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
    except OSError as e:
        raise ValueError(f"cannot read ({e.strerror})") from None
    finally:
        os.close(fd)
    data = b"".join(chunks)
    if len(data) > MAX_BYTES:
        raise ValueError(f"is larger than {_size(MAX_BYTES)}; allowed: a file of at most {_size(MAX_BYTES)}")
    return data


def _size(n: int) -> str:
    return f"{n / 2**20:g} MB ({n} bytes)"


def _too_deep(where: str = "") -> ValueError:
    return ValueError(
        f"nested deeper than {MAX_DEPTH} levels{where}; allowed: at most {MAX_DEPTH} levels of mappings and lists"
    )


def check_depth(obj: Any) -> None:
    """ValueError if ``obj`` (parsed JSON) nests mappings and lists deeper than :data:`MAX_DEPTH`;
    iterative, so the check itself cannot exceed Python's recursion limit."""
    stack = [(obj, 1)]
    while stack:
        o, d = stack.pop()
        if isinstance(o, (dict, list)):
            if d > MAX_DEPTH:
                raise _too_deep()
            stack.extend((v, d + 1) for v in (o.values() if isinstance(o, dict) else o))


def json_file(path: str | Path) -> Any:
    """A JSON file read within the limits (ValueError, one line, the path not named)."""
    raw = read_bytes(path)
    try:
        data = json.loads(raw.decode("utf-8"))
    except UnicodeDecodeError as e:
        raise ValueError(
            f"not UTF-8 text (byte 0x{raw[e.start]:02x} at offset {e.start}); allowed: a JSON file"
        ) from None
    except RecursionError:  # deeper than the parser's own limit (about 1000 levels)
        raise _too_deep() from None
    except ValueError as e:
        raise ValueError(f"malformed JSON ({e})") from None
    check_depth(data)
    return data


def check_yaml(text: str, loader: type) -> None:
    """ValueError if the YAML document ``text`` nests deeper than :data:`MAX_DEPTH` (its aliases
    expanded), holds an alias of a collection that is still open (a recursive structure: ``x: &a
    [*a]``), or holds more than :data:`MAX_VALUES` values, its aliases expanded (the message says
    whether aliases did it: a plain list of 4 million numbers is not an alias bomb). Reads the
    parser's events only (no recursion), before PyYAML's composer, which recurses once per level.
    A malformed document raises the parser's own yaml.YAMLError."""
    open_anchors: list[str | None] = []
    done: dict[str, tuple[int, int]] = {}  # anchor -> (values, levels of nesting) of its node
    frames = [[0, 0]]  # per open collection: values below it, deepest nesting below it
    aliased = [False]  # whether an alias has expanded to more than itself (for the message)

    def add(values: int, levels: int, mark: yaml.Mark) -> None:
        frames[-1][0] += values
        frames[-1][1] = max(frames[-1][1], levels)
        if len(frames) - 1 + levels > MAX_DEPTH:
            raise _too_deep(f" (line {mark.line + 1})")
        if frames[-1][0] > MAX_VALUES:
            how = "expands through its aliases to" if aliased[0] else "holds"
            raise ValueError(f"{how} more than {MAX_VALUES} values (line {mark.line + 1}); allowed: at most that many")

    for ev in yaml.parse(text, Loader=loader):
        if isinstance(ev, yaml.CollectionStartEvent):
            if len(frames) > MAX_DEPTH:
                raise _too_deep(f" (line {ev.start_mark.line + 1})")
            open_anchors.append(ev.anchor)
            frames.append([1, 0])
        elif isinstance(ev, yaml.CollectionEndEvent):
            values, below = frames.pop()
            anchor = open_anchors.pop()
            if anchor is not None:
                done[anchor] = (values, below + 1)
            add(values, below + 1, ev.start_mark)
        elif isinstance(ev, yaml.ScalarEvent):
            if ev.anchor is not None:
                done[ev.anchor] = (1, 0)
            add(1, 0, ev.start_mark)
        elif isinstance(ev, yaml.AliasEvent):
            if ev.anchor in open_anchors:
                raise ValueError(
                    f"the alias *{ev.anchor} (line {ev.start_mark.line + 1}) is inside the collection "
                    f"&{ev.anchor} it refers to (a structure that holds itself); allowed: aliases of "
                    "values already complete"
                )
            values, levels = done.get(ev.anchor, (1, 0))  # an undefined one: the composer says so
            aliased[0] = aliased[0] or values > 1
            add(values, levels, ev.start_mark)
