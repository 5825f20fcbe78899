#!/usr/bin/python3
"""The folders of src/ballagg form one-way layers: a folder includes only itself and the
folders of lower layers (docs/architecture.md).

Fails (exit status 1, one line per hit: FILE:LINE: what was found) when
  * a file includes "ballagg/FOLDER/..." of its own layer or of a higher one,
  * a file lies in, or includes, a folder of src/ballagg that LAYERS does not place,
  * a file of src/ includes a header by any other path than "ballagg/FOLDER/FILE",
  * a component target of src/CMakeLists.txt (ballagg_FOLDER) links a target of its own
    layer or of a higher one.
apps/ and python/ stand above every layer: they may include any folder. tests/ and bench/
may include anything and are not read.

Usage: /usr/bin/python3 tests/tools/check_layers.py [REPOSITORY_ROOT]
Before reading the sources, the script checks its rule on the samples below, so that a
broken rule fails the test instead of passing everything. Standard library only.
"""
import os
import re
import sys

# The layers of src/ballagg, bottom first. Folders on one line share a layer and may not
# include each other.
LAYERS = [
    ["core"],                # state, vectors, random numbers, byte streams, bad-input errors
    ["spatial"],             # cell grids, neighbour search, walls
    ["collision"],           # contact times, collision laws and their settings
    ["engines", "analysis"], # ed, ed-naive, ts, rigid-body; measurements of a state
    ["config"],              # TOML to a checked Config, input files
    ["io"],                  # file formats: CSV, XYZ, H5MD, checkpoints, run tables
    ["initial"],             # the state at t = 0
    ["run"],                 # one run and its directory: simulate, checkpoint, analyze, verify
    ["sweep", "render"],     # many runs (MPI); pictures and films
]

# Folders of the repository above every layer (their files may include any layer), each
# with the name its files go by in messages.
TOP_FOLDERS = ["apps", "python"]

# File endings read.
SOURCE_SUFFIXES = (".hpp", ".cpp", ".h", ".hpp.in")

INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^">]+)[">]')

RANK = {folder: rank for rank, folders in enumerate(LAYERS) for folder in folders}
TOP_RANK = len(LAYERS)


def included_path(line):
    """(delimiter, path) of an #include line, or None."""
    m = INCLUDE.match(line)
    return (m.group(1), m.group(2)) if m else None


def problem(source_folder, delimiter, path):
    """What is wrong with including `path` from a file of `source_folder` (a layer folder,
    or "apps"/"python"), or None. Includes of the system and of libraries (<...> not naming
    ballagg/) are not this check's business."""
    in_src = source_folder not in TOP_FOLDERS
    if not path.startswith("ballagg/"):
        if delimiter == '"' and in_src:
            return f'"{path}": include a header of src/ as "ballagg/FOLDER/FILE"'
        return None
    parts = path.split("/")
    if len(parts) < 3:
        return f'"{path}": a header directly in ballagg/, outside every layer folder'
    target = parts[1]
    if target not in RANK:
        return f'"{path}": folder "{target}" is not in the layer table (tests/tools/check_layers.py, LAYERS)'
    if target == source_folder:
        return None
    source_rank = RANK.get(source_folder, TOP_RANK)
    if RANK[target] < source_rank:
        return None
    if RANK[target] == source_rank:
        return f'"{path}": {source_folder} and {target} share a layer and may not include each other'
    return f'"{path}": {source_folder} includes {target}, a higher layer (an include that points up)'


def link_problem(source_folder, target_folder):
    """What is wrong with component target ballagg_<source_folder> linking
    ballagg_<target_folder>, or None."""
    if target_folder not in RANK:
        return None  # not a layer's component (an umbrella or a third-party target)
    if RANK[target_folder] < RANK[source_folder]:
        return None
    return f"ballagg_{source_folder} links ballagg_{target_folder}, a target of its own layer or a higher one"


# (source folder, include line, is it allowed?): the rule's own test.
SAMPLES = [
    ("engines", '#include "ballagg/core/state.hpp"', True),
    ("engines", '#include "ballagg/engines/engine.hpp"', True),
    ("core", '#include "ballagg/spatial/cell_grid.hpp"', False),
    ("collision", '#include "ballagg/engines/engine.hpp"', False),
    ("engines", '#include "ballagg/analysis/overlap.hpp"', False),
    ("analysis", '#include "ballagg/engines/engine.hpp"', False),
    ("io", '#include "ballagg/config/config.hpp"', True),
    ("io", '#include "ballagg/initial/initial_state.hpp"', False),
    ("render", '#include "ballagg/sweep/sweep_runner.hpp"', False),
    ("run", '  #  include <ballagg/io/frame.hpp>', True),
    ("spatial", '#include <ballagg/run/simulation.hpp>', False),
    ("io", '#include "ballagg/nowhere/thing.hpp"', False),
    ("core", '#include "ballagg/version.hpp"', False),
    ("core", '#include "state.hpp"', False),
    ("core", '#include <vector>', True),
    ("core", '#include <Eigen/Core>', True),
    ("apps", '#include "ballagg/sweep/sweep_runner.hpp"', True),
    ("python", '#include "bindings.hpp"', True),
    ("core", '// #include "ballagg/run/simulation.hpp"', True),
]
LINK_SAMPLES = [
    ("engines", "core", True),
    ("io", "config", True),
    ("core", "spatial", False),
    ("analysis", "engines", False),
    ("run", "lib", True),
]


def self_test():
    ok = True
    for folder, line, allowed in SAMPLES:
        found = included_path(line)
        wrong = found is not None and problem(folder, *found)
        if bool(wrong) == allowed:
            print(f"check_layers.py: rule self-test: {folder}: {line!r} should be {'allowed' if allowed else 'refused'}")
            ok = False
    for source, target, allowed in LINK_SAMPLES:
        if bool(link_problem(source, target)) == allowed:
            print(f"check_layers.py: rule self-test: ballagg_{source} -> ballagg_{target} should be "
                  f"{'allowed' if allowed else 'refused'}")
            ok = False
    return ok


def sources(root):
    """(relative path, folder it belongs to) of every source file read."""
    layer_root = os.path.join(root, "src", "ballagg")
    for folder, subfolders, names in os.walk(layer_root):
        subfolders.sort()
        for name in sorted(names):
            if name.endswith(SOURCE_SUFFIXES):
                relative = os.path.relpath(os.path.join(folder, name), layer_root)
                parts = relative.split(os.sep)
                yield os.path.join("src", "ballagg", relative), parts[0] if len(parts) > 1 else None
    for top in TOP_FOLDERS:
        for folder, subfolders, names in os.walk(os.path.join(root, top)):
            subfolders.sort()
            for name in sorted(names):
                if name.endswith(SOURCE_SUFFIXES):
                    yield os.path.relpath(os.path.join(folder, name), root), top


def include_hits(root):
    for relative, folder in sources(root):
        if folder is None:
            yield f"{relative}:1: a file directly in src/ballagg/, outside every layer folder"
            continue
        if folder not in RANK and folder not in TOP_FOLDERS:
            yield f'{relative}:1: folder "{folder}" is not in the layer table (tests/tools/check_layers.py, LAYERS)'
            continue
        with open(os.path.join(root, relative), encoding="utf-8") as f:
            for number, line in enumerate(f, 1):
                found = included_path(line)
                why = found and problem(folder, *found)
                if why:
                    yield f"{relative}:{number}: {why}"


def link_hits(root):
    """Links between component targets in src/CMakeLists.txt that point up."""
    relative = os.path.join("src", "CMakeLists.txt")
    with open(os.path.join(root, relative), encoding="utf-8") as f:
        text = f.read()
    for m in re.finditer(r"target_link_libraries\s*\(\s*ballagg_(\w+)([^)]*)\)", text):
        source = m.group(1)
        if source not in RANK:
            continue
        line = text.count("\n", 0, m.start()) + 1
        for target in re.findall(r"\bballagg_(\w+)", m.group(2)):
            why = link_problem(source, target)
            if why:
                yield f"{relative}:{line}: {why}"


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.dirname(os.path.dirname(
        os.path.abspath(__file__))))
    if not self_test():
        return 1
    found = list(include_hits(root)) + list(link_hits(root))
    for line in found:
        print(line)
    if found:
        print(f"check_layers.py: {len(found)} include(s) or link(s) against the layers (docs/architecture.md)")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
