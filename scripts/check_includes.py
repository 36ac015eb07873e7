#!/usr/bin/python3
"""Checks the include structure of the library's layers (issue 45):

- no cycle among the components of a layer, a component being a header and the source of the
  same name (x.hpp with x.cpp, as Lakos counts them): x.cpp including y.hpp while y.cpp
  includes x.hpp is a cycle;
- no layer includes another layer's internal headers (`mimpact/<layer>/internal/...` or a
  header in another layer's `src/`);
- a layer includes only the layers below it (docs/architecture.md).

    /usr/bin/python3 scripts/check_includes.py [--dot FILE]   (--dot: the component graph)

Exits 1 naming every cycle and every include across a boundary.
"""
import argparse
import collections
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
# each layer and the layers it may include (docs/architecture.md)
BELOW = {"common": set(), "numerics": {"common"}, "analysis": {"common", "numerics"},
         "kernel": {"common", "numerics"}, "plugins": {"common", "numerics", "kernel"}}
BELOW["granular"] = BELOW["plugins"] | {"plugins", "analysis"}
BELOW["chains"] = BELOW["packings"] = BELOW["granular"] | {"granular"}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def layer_of(path):
    return path.split("/")[0]


def component(path):
    return Path(path).stem


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--dot", help="write the components' include graph here (Graphviz)")
    args = parser.parse_args()
    files = subprocess.run(["git", "ls-files", *BELOW], cwd=ROOT, capture_output=True,
                           text=True, check=True).stdout.split()
    files = [f for f in files if f.endswith((".cpp", ".hpp"))]
    by_name = {}
    for f in files:
        by_name.setdefault(Path(f).name, []).append(f)
    problems = []
    graph = collections.defaultdict(set)  # (layer, component) -> components it includes
    for f in files:
        layer = layer_of(f)
        for included in INCLUDE.findall((ROOT / f).read_text()):
            parts = included.split("/")
            if parts[0] == "mimpact" and len(parts) > 2:
                target_layer = parts[1]
                if target_layer != layer and "internal" in parts[2:-1]:
                    problems.append(f"{f}: includes {target_layer}'s internal header {included}")
                if target_layer != layer and target_layer not in BELOW[layer]:
                    problems.append(f"{f}: includes {included}, a layer not below {layer}")
                if target_layer == layer:
                    graph[(layer, component(f))].add((layer, component(included)))
            else:  # a header beside the source, in the layer's src/
                candidates = [c for c in by_name.get(Path(included).name, [])
                              if Path(c).parent == Path(f).parent]
                if candidates:
                    graph[(layer, component(f))].add((layer, component(candidates[0])))
    for node in graph:
        graph[node].discard(node)
    problems += [f"cycle in {cycle[0][0]}: " + " -> ".join(c for _, c in cycle)
                 for cycle in cycles(graph)]
    if args.dot:
        with open(args.dot, "w") as out:
            out.write("digraph includes {\n")
            for (layer, name), targets in sorted(graph.items()):
                for _, target in sorted(targets):
                    out.write(f'  "{layer}/{name}" -> "{layer}/{target}";\n')
            out.write("}\n")
    print(*problems, sep="\n") if problems else None
    print(f"includes: {len(files)} files, {len(graph)} components; {len(problems)} problems")
    return 1 if problems else 0


def cycles(graph):
    """One cycle per strongly connected component of more than one node (Tarjan)."""
    index, low, stack, on_stack, found, counter = {}, {}, [], set(), [], [0]

    def visit(node):
        index[node] = low[node] = counter[0]
        counter[0] += 1
        stack.append(node)
        on_stack.add(node)
        for target in graph.get(node, ()):
            if target not in index:
                visit(target)
                low[node] = min(low[node], low[target])
            elif target in on_stack:
                low[node] = min(low[node], index[target])
        if low[node] == index[node]:
            members = []
            while True:
                member = stack.pop()
                on_stack.discard(member)
                members.append(member)
                if member == node:
                    break
            if len(members) > 1:
                found.append(sorted(members) + [sorted(members)[0]])

    for node in list(graph):
        if node not in index:
            visit(node)
    return found


if __name__ == "__main__":
    sys.exit(main())
