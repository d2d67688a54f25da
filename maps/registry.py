"""The scene registry: every name a command or a function accepts as a scene.

A name is looked up, in order, among

1. the built-in scenes (:data:`maps.scenes.SCENES`: the thesis model and the impact oscillator);
2. the scenes registered in this process (:func:`register_scene`);
3. ``package.module:NAME``: the object ``NAME`` of an importable module (a :class:`Scene`, a
   :class:`~maps.hybrid.HybridSystem` or a function returning one), so that a fresh command-line
   process or a spawned worker finds a user's system by its address;
4. the entry points of the group ``maps.scenes`` of the installed distributions
   (``[project.entry-points."maps.scenes"] my-scene = "package.module:NAME"``).

>>> import maps
>>> maps.register_scene(my_system, name="my-ball", defaults={"g": 9.81}, x0={"x": 0.1})
>>> maps.StroboscopicMap("my-ball", {"g": 9.81, ...})       # or maps.problem("my-ball")
"""
from __future__ import annotations

import copyreg
import importlib
from dataclasses import replace
from importlib.metadata import entry_points

from .hybrid import HybridSystem
from .parameters import ParameterError
from .scenes import SCENES, Scene, SystemBuilder

#: the entry-point group that installed distributions declare their scenes in
ENTRY_POINT_GROUP = "maps.scenes"

_REGISTERED: dict = {}


def register_scene(scene, name: str | None = None, *, summary: str = "", defaults: dict | None = None,
                   x0: dict | None = None, replace: bool = False) -> Scene:
    """Make ``scene`` known by ``name`` to every function and command of this process.

    ``scene``: a :class:`Scene`, a :class:`~maps.hybrid.HybridSystem`, or a function returning one
    (a module-level function pickles by reference: worker processes rebuild the system from it).
    ``defaults``: {parameter: value} used when a parameter is not given; ``x0``: the default start
    {state: value} [SI]; ``summary``: one line for ``bifurc scenes``.  A built-in scene's name is
    refused; another registered one's unless ``replace=True``.  Returns the registered Scene.
    """
    sc = as_scene(scene, name=name, summary=summary, defaults=defaults, x0=x0)
    if sc.name in SCENES:
        raise ParameterError(f"scene name {sc.name!r} is a built-in scene's; choose another name")
    if sc.name in _REGISTERED and not replace:
        raise ParameterError(f"scene {sc.name!r} is already registered; pass replace=True to replace it")
    _REGISTERED[sc.name] = sc
    return sc


def unregister_scene(name: str) -> None:
    """Forget the scene registered as ``name`` in this process (a built-in one cannot be)."""
    if name not in _REGISTERED:
        raise ParameterError(f"no scene {name!r} is registered in this process")
    del _REGISTERED[name]


def as_scene(obj, name: str | None = None, *, summary: str = "", defaults: dict | None = None,
             x0: dict | None = None) -> Scene:
    """A :class:`Scene` from a Scene (returned as is), a HybridSystem or a function returning one."""
    if isinstance(obj, Scene):
        return obj
    if isinstance(obj, HybridSystem):
        builder, system = SystemBuilder(obj), obj
    elif callable(obj):
        builder, system = obj, None
    else:
        raise ParameterError(f"a scene must be a maps.Scene, a maps.HybridSystem or a function returning one; "
                             f"got {type(obj).__name__}")
    sc_name = name or (system.name if system is not None else getattr(obj, "__name__", None))
    if not sc_name:
        raise ParameterError("give the scene a name (name=...)")
    overrides = {k: (float(v), f"scene {sc_name} default") for k, v in (defaults or {}).items()}
    sc = Scene(str(sc_name), summary or (f"user system {system.name!r}" if system is not None else "user system"),
               None, preset=None, overrides=overrides, x0=dict(x0 or {}), builder=builder)
    unknown = sorted(set(overrides) - set(sc.system.param_names))
    if unknown:
        raise ParameterError(f"default {unknown[0]!r} is not a parameter of scene {sc.name!r}; its parameters are: "
                             f"{', '.join(sc.system.param_names)}")
    return sc


def get_scene(scene) -> Scene:
    """The scene ``scene`` names (a :class:`Scene` passes through; a HybridSystem is wrapped)."""
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, HybridSystem):
        return as_scene(scene)
    if not isinstance(scene, str):
        raise ParameterError(f"scene must be a name, a maps.Scene or a maps.HybridSystem; got {type(scene).__name__}")
    if scene in SCENES:
        return SCENES[scene]
    if scene in _REGISTERED:
        return _REGISTERED[scene]
    if ":" in scene:
        return _from_address(scene, scene)
    found = _entry_points().get(scene)
    if found is not None:
        return _from_address(found, scene)
    raise ParameterError(f"unknown scene {scene!r}; scenes: {', '.join(scene_names())} "
                         f"(or package.module:NAME, or register_scene)")


def scene_names() -> list[str]:
    """Every scene name: built-in, registered in this process, then installed entry points."""
    names = list(SCENES) + [n for n in _REGISTERED if n not in SCENES]
    return names + [n for n in _entry_points() if n not in names]


def _entry_points() -> dict:
    """name -> "module:attr" of the installed ``maps.scenes`` entry points."""
    return {ep.name: ep.value for ep in entry_points(group=ENTRY_POINT_GROUP)}


def _from_address(address: str, name: str) -> Scene:
    """The scene at ``package.module:NAME`` (named ``name``)."""
    module, _, attr = address.partition(":")
    try:
        obj = importlib.import_module(module)
        for part in attr.split("."):
            obj = getattr(obj, part)
    except (ImportError, AttributeError) as exc:
        raise ParameterError(f"scene {name!r}: cannot load {address!r} ({type(exc).__name__}: {exc})") from None
    return replace(as_scene(obj, name=name), name=name, address=address)


def _scene_at(address: str, name: str, options, chosen) -> Scene:
    """The scene loaded from ``address`` with ``options`` applied (how a loaded scene unpickles)."""
    sc = _from_address(address, name)
    return replace(sc, options=options, chosen=chosen) if options is not None else sc


def _reduce_scene(sc: Scene):
    """A scene loaded from an address pickles as that address (its system is rebuilt from it in
    another process); any other scene field by field (its builder by reference)."""
    if sc.address is not None:
        return _scene_at, (sc.address, sc.name, sc.options, sc.chosen)
    return object.__reduce_ex__(sc, 2)


copyreg.pickle(Scene, _reduce_scene)
