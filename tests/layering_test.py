#!/usr/bin/env python3
"""The layers of docs/architecture.md: the rooms of engine/ and farm/, checked on the sources.

    layering_test.py SOURCE_DIR
    layering_test.py --self-test    shows that it fails on a tree with each kind of problem

Fails (exit 1, one line per finding) when
- a file includes a header of a room it may not use (each room uses only the rooms below it);
- a project header is included by a bare name rather than its path from the repository root;
- mpi.h is included outside farm/cluster/, libav* outside farm/output/, Qt outside farm/view/;
- two modules (a .h/.cpp pair) of the project depend on each other, directly or through
  others: a circle of includes, such as a.cpp including b.h while b.cpp includes a.h.
"""
import os
import re
import sys

# room -> the rooms its files may include from (itself always). farm/main.cpp and tools/ join
# every room, so they may use all of them. The engine's rooms, bottom up: each may use those
# below it (engine/CMakeLists.txt says what each holds).
ENGINE_ROOMS = ["engine/util", "engine/geometry", "engine/materials", "engine/lights", "engine/scene",
                "engine/integrators", "engine/load/gltf", "engine/load/assimp", "engine/load"]
ALLOWED = {room: ENGINE_ROOMS[:i] for i, room in enumerate(ENGINE_ROOMS)}
ENGINE = ENGINE_ROOMS
ALLOWED.update({
    "anim": ENGINE,
    # engine: the signal handlers stop a load in progress (engine/util/load_control.h), and usage
    # errors are made printable as input errors are (engine/util/errors.h).
    "farm/process": ENGINE,
    "farm/output": ["farm/process", "anim"] + ENGINE,
    "farm/cluster": ["farm/output", "farm/process", "anim"] + ENGINE,
    "farm/cli": ["farm/output", "farm/process", "anim"] + ENGINE,
    "farm/commands": ["farm/cli", "farm/cluster", "farm/output", "farm/process", "anim"] + ENGINE,
    # report/stability/: the stability catalogue's cases, over the engine alone (the engine's
    # tests assert them too).
    "farm/report/stability": ENGINE,
    "farm/report": ["farm/cli", "farm/output", "farm/process", "farm/report/stability", "anim"] + ENGINE,
    "farm/view": ["farm/commands", "farm/cli", "farm/cluster", "farm/output", "farm/process", "anim"] + ENGINE,
    "farm": "*",
    "tools/pgo": "*",
})
# System headers that belong to one room only.
ONLY_IN = [
    (re.compile(r"^mpi\.h$"), "farm/cluster"),
    (re.compile(r"^libav"), "farm/output"),
    (re.compile(r"^Q[A-Za-z]*(/|$)|^QtCore|^QtGui|^QtWidgets"), "farm/view"),
    (re.compile(r"^assimp/"), "engine/load/assimp"),
]
INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]', re.M)


def room_of(rel):
    d = os.path.dirname(rel)
    while d and d not in ALLOWED:
        d = os.path.dirname(d)
    return d or None


def check(src):
    files = []
    for top in ("engine", "anim", "farm", "tools"):
        for root, _, names in os.walk(os.path.join(src, top)):
            for n in names:
                if n.endswith((".h", ".cpp", ".inc")):
                    files.append(os.path.relpath(os.path.join(root, n), src))
    header_room = {f: room_of(f) for f in files if f.endswith((".h", ".inc"))}
    problems = []
    deps = {}  # module (path without extension) -> modules it includes
    for f in files:
        room = room_of(f)
        if room is None:
            problems.append(f"{f}: in no room of tests/layering_test.py")
            continue
        text = open(os.path.join(src, f), encoding="utf-8", errors="replace").read()
        module = os.path.splitext(f)[0]
        for kind, name in INCLUDE.findall(text):
            for pattern, only in ONLY_IN:
                if pattern.search(name) and room != only and not room.startswith(only + "/"):
                    problems.append(f"{f}: includes <{name}>, which only {only}/ may include")
            if kind != '"':
                continue
            if name not in header_room:
                # Project headers are named from the repository root ("engine/geometry/bvh.h"),
                # so an include says where it points; anything else is a third-party header.
                if os.path.basename(name) in {os.path.basename(h) for h in header_room}:
                    problems.append(f"{f}: includes \"{name}\", not named from the repository root")
                continue
            target = header_room[name]
            allowed = ALLOWED[room]
            if target != room and allowed != "*" and target not in allowed:
                problems.append(f"{f}: includes {name}, but {room}/ may not use {target}/")
            target_module = os.path.splitext(name)[0]
            if target_module != module:
                deps.setdefault(module, set()).add(target_module)
    # Circles between modules: Tarjan's strongly connected components.
    index, low, on_stack, stack, counter = {}, {}, set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on_stack.add(v)
        for w in sorted(deps.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                problems.append("include circle: " + " -> ".join(sorted(component)))

    sys.setrecursionlimit(10000)
    for v in sorted(deps):
        if v not in index:
            visit(v)
    return files, deps, problems


def self_test():
    """A small tree with an arrow up the layers, a circle and mpi.h out of its room: each must
    be found, and the same tree without them must pass."""
    import tempfile
    with tempfile.TemporaryDirectory() as d:
        def write(rel, text):
            os.makedirs(os.path.join(d, os.path.dirname(rel)), exist_ok=True)
            open(os.path.join(d, rel), "w").write(text)
        write("engine/util/a.h", "#pragma once\n")
        write("engine/util/a.cpp", '#include "engine/util/a.h"\n#include "engine/util/b.h"\n')
        write("engine/util/b.h", "#pragma once\n")
        write("engine/util/b.cpp", '#include "engine/util/b.h"\n')
        write("engine/scene/s.h", '#pragma once\n#include "engine/util/a.h"\n')
        write("farm/cluster/t.cpp", "#include <mpi.h>\n")
        _, _, clean = check(d)
        write("engine/util/b.cpp", '#include "engine/util/b.h"\n#include "engine/util/a.h"\n')  # a circle
        write("engine/util/c.cpp", '#include "anim/timeline.h"\n')   # engine -> anim
        write("engine/util/d.cpp", '#include "engine/scene/s.h"\n')  # util -> scene, a floor up
        write("engine/util/e.cpp", '#include "s.h"\n')               # a bare name
        write("anim/timeline.h", "#pragma once\n")
        write("farm/output/sink.cpp", "#include <mpi.h>\n")          # mpi.h outside cluster/
        _, _, found = check(d)
    want = ["include circle", "may not use anim/", "engine/util/ may not use engine/scene/", "not named from the repository root",
            "only farm/cluster/ may include"]
    missing = [w for w in want if not any(w in p for p in found)]
    if clean or missing:
        print("FAIL: self-test: clean tree gave", clean, "; not found:", missing)
        return 1
    print(f"layering self-test: {len(found)} problems found in the broken tree, none in the clean one")
    return 0


def main():
    if sys.argv[1] == "--self-test":
        return self_test()
    files, deps, problems = check(sys.argv[1])
    for p in problems:
        print("FAIL:", p)
    print(f"layering: {len(files)} files, {sum(len(d) for d in deps.values())} module dependencies, "
          f"{len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
