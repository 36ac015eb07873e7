"""Dotted paths into a scene: "contact.restitution", "strikers.0.velocity",
"chain.segments.1.taper". A component that is an integer indexes a list; any other names a key
of an object, which may be absent from the scene as long as the scene format has it (the
scene's parser checks that, with its messages)."""

import copy
import os

from ._mimpact import read_scene


def scene_dict(scene):
    """A scene given as a file's path or as a dict, as a dict of its own (a deep copy)."""
    if isinstance(scene, dict):
        return copy.deepcopy(scene)
    if isinstance(scene, (str, os.PathLike)):
        return read_scene(scene)
    raise ValueError(f"scene = {scene!r} is not allowed; allowed: a scene file's path or a dict "
                     "with its keys")


def _place(scene, path):
    """The container holding the last component of `path`, and that component."""
    if not isinstance(path, str) or not path or any(not part for part in path.split(".")):
        raise ValueError(f"path {path!r} is not allowed; allowed: keys and list indices joined "
                         "by dots, such as 'strikers.0.velocity'")
    parts = path.split(".")
    node, walked = scene, []
    for part in parts[:-1]:
        node = _child(node, part, walked, path, create=True)
        walked.append(part)
    last = parts[-1]
    if isinstance(node, list):
        return node, _index(node, last, walked, path)
    if not isinstance(node, dict):
        raise ValueError(f"path {path!r}: {'.'.join(walked)} is a value, not an object or a list")
    return node, last


def _index(node, part, walked, path):
    where = ".".join(walked)
    if not part.isdigit():
        raise ValueError(f"path {path!r}: {where} is a list; {part!r} is not allowed; allowed: "
                         f"an index 0 <= i < {len(node)}")
    index = int(part)
    if index >= len(node):
        raise ValueError(f"path {path!r}: {where} has {len(node)} entries; index {index} is not "
                         f"allowed; allowed: 0 <= i < {len(node)}")
    return index


def _child(node, part, walked, path, create):
    if isinstance(node, list):
        return node[_index(node, part, walked, path)]
    if not isinstance(node, dict):
        raise ValueError(f"path {path!r}: {'.'.join(walked)} is a value, not an object or a list")
    if part not in node:
        if not create:
            raise ValueError(f"path {path!r}: the scene has no {'.'.join(walked + [part])}")
        node[part] = {}
    return node[part]


def set_path(scene, path, value):
    """Sets the value at a dotted path of a scene dict, in place."""
    container, key = _place(scene, path)
    container[key] = value


def get_path(scene, path):
    """The value at a dotted path of a scene dict."""
    node, walked = scene, []
    for part in path.split("."):
        node = _child(node, part, walked, path, create=False)
        walked.append(part)
    return node
