"""UUV Simulator's hydrodynamic and thruster tags of a URDF (``docs/models.md``, "UUV Simulator and Gazebo files").

UUV Simulator (Manhaes et al., "UUV Simulator: A Gazebo-based package for underwater intervention and
multi-robot simulation", OCEANS 2016; Apache-2.0) describes a vehicle's hydrodynamics inside ``<gazebo>``
blocks of its URDF: a ``libuuv_underwater_object_ros_plugin`` plugin holding, per ``<link name=...>``,
``volume``, ``center_of_buoyancy``, ``neutrally_buoyant`` and a ``hydrodynamic_model``; and one
``libuuv_thruster_ros_plugin`` per thruster. This module reads them (facts from UUV Simulator's
``HydrodynamicModel.cc``, ``BuoyantObject.cc``, ``ThrusterPlugin.cc``) into uvms's per-link hydrodynamics:

* **Frames.** UUV's Fossen model works in the link's axes turned to x forward, y starboard, z down
  (``HydrodynamicModel::ToNED`` flips y and z of the Gazebo link's x-forward, y-left, z-up axes) and
  linear-first order ``[u v w p q r]``. uvms keeps the URDF link's own axes and ``[angular; linear]``: every
  6x6 matrix becomes ``H6 P M P^T H6`` (``P`` the reorder, :func:`uvms.spatial.from_linear_first`, ``H6 =
  diag(1, -1, -1, 1, -1, -1)`` the half turn, ``docs/conventions.md``, "Frames"). ``center_of_buoyancy`` is
  already in the link's own axes.
* **Added mass** ``M_A = scaling_added_mass (added_mass + offset_added_mass 1)`` (36 values, row major, the
  physical positive matrix), made symmetric (``(M + M^T) / 2``; the asymmetry is reported). uvms puts it in
  the articulated inertia (no lagged acceleration, as UUV's filtered finite difference is).
* **Damping** (``HMFossen::ComputeDampingMatrix``): UUV's values are derivatives (negative), its force
  ``scaling_damping ((D_lin + o_l 1) nu + u (D_lfs + o_lfs 1) nu + diag(D_nl + o_nl) diag|nu| nu)``; uvms's
  ``D_l = -scaling (D_lin + o_l 1)``, ``D_q = -scaling diag(D_nl + o_nl)`` (the quadratic matrix's diagonal
  only, as UUV uses), and the forward-speed term as mixed quadratic damping ``C[1, i, j, u] = -scaling
  (D_lfs + o_lfs 1)[i, j]`` (:attr:`uvms.model.model.Model.damping_cross`), all about the link origin.
* **Buoyancy**: ``rho max(0, scaling_volume (volume + offset_volume))`` at ``center_of_buoyancy``; a
  ``neutrally_buoyant`` link displaces its own mass (with the links fixed to it, as Gazebo lumps them). The
  surface-vessel terms (``metacentric_width`` ...) are not mapped (reported).
* **Shapes**: ``hydrodynamic_model`` types ``sphere``, ``cylinder`` (``axis`` i / j / k) and ``spheroid``
  become uvms shapes (:mod:`uvms.hydro.shapes`), whose added mass uvms computes; their drag coefficient is
  ``<cd>`` when given, else none (UUV's Reynolds-dependent drag is not mapped, reported).
* **Thrusters**: ``dynamics`` ``ZeroOrder`` -> ``ideal``, ``FirstOrder`` -> ``first_order`` with
  ``timeConstant`` (UUV lags the rotor command before its conversion; uvms lags the thrust: the same for a
  linear conversion, an approximation for ``Basic``, reported); the steady limits from ``thrustMin`` /
  ``thrustMax`` and the conversion (``Basic``: ``T = rotorConstant x |x|``; ``LinearInterp``: the table) at
  ``clampMin`` / ``clampMax`` times ``gain`` and the efficiencies, the smaller magnitude of the two ends
  (uvms's ideal and first-order thrusters are symmetric). The thrust acts along the thruster joint's axis at
  the thruster link's origin, whose spin joint is frozen (it is the rotor, not a degree of freedom).

Everything else inside these plugins, and every other ``<gazebo>`` block, is listed in one warning.
"""

from __future__ import annotations

import io
import math
import numpy as np

from uvms.errors import UvmsInputError
from uvms.model.gazebo import LinkTags, PluginTags, ThrusterTags

UNDERWATER_PLUGIN = "uuv_underwater_object"
THRUSTER_PLUGIN = "uuv_thruster"
FOSSEN_TAGS = ("added_mass", "linear_damping", "linear_damping_forward_speed", "quadratic_damping",
               "scaling_added_mass", "offset_added_mass", "scaling_damping", "offset_linear_damping",
               "offset_lin_forward_speed_damping", "offset_nonlin_damping")
LINK_TAGS = ("volume", "scaling_volume", "offset_volume", "center_of_buoyancy", "neutrally_buoyant",
             "hydrodynamic_model")
PLUMBING = ("flow_velocity_topic", "debug", "robotNamespace", "use_global_current_velocity")
"""Plugin tags about ROS topics and logging: nothing physical to map; left out of the ignored list."""
_H6 = np.array([1.0, -1.0, -1.0, 1.0, -1.0, -1.0])
_REORDER = np.array([3, 4, 5, 0, 1, 2])          # uvms index -> UUV (linear-first) index


def _numbers(element, source: str, where: str, sizes=None) -> np.ndarray:
    text = (element.text or "").split()
    try:
        values = np.array([float(x) for x in text])
    except ValueError:
        raise UvmsInputError(f"expected numbers, found {' '.join(text)[:60]!r}", source, where) from None
    if not np.all(np.isfinite(values)):
        raise UvmsInputError("expected finite numbers, found NaN or infinity", source, where)
    if sizes is not None and values.size not in sizes:
        raise UvmsInputError(f"expected {' or '.join(map(str, sizes))} numbers, found {values.size}", source, where)
    return values


def _number(parent, tag: str, default: float, source: str, where: str) -> float:
    element = parent.find(tag)
    if element is None:
        return default
    return float(_numbers(element, source, f"{where}.{tag}", (1,))[0])


def _matrix(values: np.ndarray) -> np.ndarray:
    """6 (diagonal) or 36 (row major) values as a 6x6 matrix."""
    return np.diag(values) if values.size == 6 else values.reshape(6, 6)


def to_uvms_matrix(M_uuv: np.ndarray) -> np.ndarray:
    """A UUV 6x6 matrix (linear-first, link axes turned z down) in uvms's ``[angular; linear]`` order in the
    URDF link's own axes: ``H6 P M P^T H6``."""
    M = np.asarray(M_uuv, dtype=float)[np.ix_(_REORDER, _REORDER)]
    return _H6[:, None] * M * _H6[None, :]


def _fossen(link: LinkTags, model, source: str, where: str, notes: list[str]) -> None:
    def tag(name):
        return model.find(name)

    def scalar(name, default):
        return _number(model, name, default, source, where)

    eye = np.eye(6)
    scale_m, offset_m = scalar("scaling_added_mass", 1.0), scalar("offset_added_mass", 0.0)
    if tag("added_mass") is not None:
        M = _numbers(tag("added_mass"), source, f"{where}.added_mass", (36,)).reshape(6, 6)
        M = scale_m * (M + offset_m * eye)
        asym = float(np.abs(M - M.T).max())
        if asym > 0.0:
            notes.append(f"link {link.name!r}: added_mass made symmetric (largest |M - M^T| {asym:.4g})")
        link.added_mass = to_uvms_matrix(0.5 * (M + M.T))
        link.origins["added mass"] = "hydrodynamic_model/added_mass"
    scale_d = scalar("scaling_damping", 1.0)
    lin = np.zeros((6, 6)) if tag("linear_damping") is None else _matrix(
        _numbers(tag("linear_damping"), source, f"{where}.linear_damping", (6, 36)))
    lin = lin + scalar("offset_linear_damping", 0.0) * eye
    quad = np.zeros(6) if tag("quadratic_damping") is None else np.diag(_matrix(
        _numbers(tag("quadratic_damping"), source, f"{where}.quadratic_damping", (6, 36))))
    quad = quad + scalar("offset_nonlin_damping", 0.0)
    fwd = np.zeros((6, 6)) if tag("linear_damping_forward_speed") is None else _matrix(
        _numbers(tag("linear_damping_forward_speed"), source, f"{where}.linear_damping_forward_speed", (6, 36)))
    fwd = fwd + scalar("offset_lin_forward_speed_damping", 0.0) * eye
    link.damping_linear = to_uvms_matrix(-scale_d * lin)
    link.damping_quadratic = to_uvms_matrix(np.diag(-scale_d * quad))
    if tag("linear_damping") is not None or tag("offset_linear_damping") is not None:
        link.origins["linear damping"] = "hydrodynamic_model/linear_damping"
    if tag("quadratic_damping") is not None or tag("offset_nonlin_damping") is not None:
        link.origins["quadratic damping"] = "hydrodynamic_model/quadratic_damping (diagonal)"
    if np.any(fwd):
        C = np.zeros((2, 6, 6, 6))
        F = to_uvms_matrix(-scale_d * fwd)          # force i, velocity j, times u (index 3 in uvms order)
        C[1, :, :, 3] = F
        link.damping_cross = C
        link.origins["forward-speed damping"] = "hydrodynamic_model/linear_damping_forward_speed"


def _box(element, source: str, where: str) -> np.ndarray | None:
    """The link's ``<box>`` (``width``, ``length``, ``height``: its x, y, z extents, ``BuoyantObject``), or None."""
    box = element.find("box")
    if box is None:
        return None
    return np.array([_number(box, tag, math.nan, source, f"{where}.box") for tag in ("width", "length", "height")])


def _shape(link: LinkTags, model, kind: str, box, source: str, where: str, notes: list[str]) -> None:
    """A shape model; without ``radius`` / ``length`` / ``axis``, UUV's defaults from the link's ``<box>``
    (``HMCylinder``, ``HMSpheroid``: the smallest extent as radius, the largest as length and axis)."""
    from uvms.hydro import shapes as hs

    usable = box is not None and bool(np.all(np.isfinite(box))) and bool(np.all(box > 0))
    cd = _number(model, "cd", 0.0, source, where)
    radius = _number(model, "radius", float(box.min()) if usable else math.nan, source, where)
    if not radius > 0:
        raise UvmsInputError(f"expected a <radius> > 0 (or the link's <box>) for a {kind} hydrodynamic model",
                             source, where)
    if kind == "sphere":
        link.shapes.append(hs.Sphere(radius, cd))
    else:
        length = _number(model, "length", float(box.max()) if usable else math.nan, source, where)
        if not length > 0:
            raise UvmsInputError(f"expected a <length> > 0 (or the link's <box>) for a {kind} hydrodynamic model",
                                 source, where)
        if kind == "cylinder":
            axis_tag = model.find("axis")
            default = "ijk"[int(np.argmax(box))] if usable else "i"
            axis = (axis_tag.text or default).strip() if axis_tag is not None else default
            direction = {"i": (1.0, 0.0, 0.0), "j": (0.0, 1.0, 0.0), "k": (0.0, 0.0, 1.0)}.get(axis)
            if direction is None:
                raise UvmsInputError(f"expected <axis> i, j or k, found {axis[:20]!r}", source, f"{where}.axis")
            link.shapes.append(hs.Cylinder(radius, length, cd, rotation=hs.rotation_from_axis(direction)))
        else:
            link.shapes.append(hs.Ellipsoid((0.5 * length, radius, radius), cd))
    link.origins["added mass"] = f"hydrodynamic_model/type {kind} (uvms shape)"
    if cd == 0.0:
        notes.append(f"link {link.name!r}: the {kind} model's drag is not mapped (no <cd>)")


def _link(element, rho_hint, source: str, tags: PluginTags) -> LinkTags:
    name = element.get("name")
    if not name:
        raise UvmsInputError("expected a name attribute on the plugin's <link>", source,
                             "gazebo/plugin (uuv_underwater_object)")
    where = f"gazebo/plugin/link {name!r}"
    link = LinkTags(name)
    for child in element:
        if child.tag not in LINK_TAGS and child.tag != "box":
            tags.ignored.append(f"{name}/{child.tag}")
    box = _box(element, source, where)
    model = element.find("hydrodynamic_model")
    shaped = model is not None and (model.findtext("type") or "").strip() in ("sphere", "cylinder", "spheroid")
    if box is not None and not shaped:
        tags.ignored.append(f"{name}/box (surface-vessel bounding box)")
    scaling, offset = (_number(element, "scaling_volume", 1.0, source, where),
                       _number(element, "offset_volume", 0.0, source, where))
    link.volume = max(0.0, scaling * (_number(element, "volume", 0.0, source, where) + offset))
    if element.find("volume") is not None:
        link.origins["buoyancy"] = "volume"
    cob = element.find("center_of_buoyancy")
    if cob is not None:
        link.center = _numbers(cob, source, f"{where}.center_of_buoyancy", (3,))
        link.origins["centre of buoyancy"] = "center_of_buoyancy"
    neutral = element.find("neutrally_buoyant")
    if neutral is not None and (neutral.text or "").strip().lower() in ("1", "true"):
        link.neutrally_buoyant = True
        link.origins["buoyancy"] = "neutrally_buoyant"
    if model is not None:
        kind_tag = model.find("type")
        kind = (kind_tag.text or "").strip() if kind_tag is not None else ""
        mwhere = f"{where}.hydrodynamic_model"
        if kind == "fossen":
            _fossen(link, model, source, mwhere, tags.notes)
            known = FOSSEN_TAGS
        elif kind in ("sphere", "cylinder", "spheroid"):
            _shape(link, model, kind, box, source, mwhere, tags.notes)
            known = ("radius", "length", "axis", "cd")
        else:
            raise UvmsInputError(f"expected a hydrodynamic_model type fossen, sphere, cylinder or spheroid, "
                                 f"found {kind[:30]!r}", source, f"{mwhere}.type")
        tags.ignored.extend(f"{name}/hydrodynamic_model/{c.tag}" for c in model
                            if c.tag != "type" and c.tag not in known)
    return link


def _conversion(element, source: str, where: str):
    """The steady thrust function ``x -> T`` of a ``<conversion>`` block."""
    if element is None:
        raise UvmsInputError("expected a <conversion> block", source, where)
    kind = (element.findtext("type") or "").strip()
    if kind == "Basic":
        k = _number(element, "rotorConstant", math.nan, source, f"{where}.conversion")
        if not math.isfinite(k):
            raise UvmsInputError("expected a <rotorConstant>", source, f"{where}.conversion")
        return lambda x: k * x * abs(x), False
    if kind == "LinearInterp":
        xs = _numbers(element.find("inputValues"), source, f"{where}.conversion.inputValues")
        ys = _numbers(element.find("outputValues"), source, f"{where}.conversion.outputValues")
        if xs.size != ys.size or xs.size < 2 or np.any(np.diff(xs) <= 0):
            raise UvmsInputError("expected as many inputValues as outputValues (at least 2), inputs increasing",
                                 source, f"{where}.conversion")
        return lambda x: float(np.interp(x, xs, ys)), True
    raise UvmsInputError(f"expected a conversion type Basic or LinearInterp, found {kind[:30]!r} (not mapped)",
                         source, f"{where}.conversion.type")


def _thruster(plugin, source: str, tags: PluginTags) -> ThrusterTags:
    where = f"gazebo/plugin {plugin.get('name') or THRUSTER_PLUGIN!r}"
    link, joint = (plugin.findtext("linkName") or "").strip(), (plugin.findtext("jointName") or "").strip()
    if not link or not joint:
        raise UvmsInputError("expected <linkName> and <jointName>", source, where)
    ident = int(_number(plugin, "thrusterID", len(tags.thrusters), source, where))
    dyn = plugin.find("dynamics")
    kind = (dyn.findtext("type") or "").strip() if dyn is not None else ""
    if kind not in ("ZeroOrder", "FirstOrder"):
        raise UvmsInputError(f"expected dynamics type ZeroOrder or FirstOrder, found {kind[:30]!r} (not mapped)",
                             source, f"{where}.dynamics")
    f, linear = _conversion(plugin.find("conversion"), source, where)
    gain = _number(plugin, "gain", 1.0, source, where)
    eff = _number(plugin, "thrust_efficiency", 1.0, source, where) * _number(plugin, "propeller_efficiency", 1.0,
                                                                            source, where)
    ends = []
    for clamp, limit, sign in (("clampMax", "thrustMax", 1.0), ("clampMin", "thrustMin", -1.0)):
        c = _number(plugin, clamp, sign * math.inf, source, where)
        T = sign * _number(plugin, limit, sign * math.inf, source, where)
        T_conv = sign * eff * f(gain * c) if math.isfinite(c) else math.inf
        ends.append(min(T, T_conv if T_conv > 0 else math.inf))
    max_thrust = min(ends)
    if ends[0] != ends[1]:
        tags.notes.append(f"thruster {ident}: limits {ends[0]:.4g} N forward, {ends[1]:.4g} N reverse; "
                          f"uvms uses +/-{max_thrust:.4g} N")
    time_constant = None
    if kind == "FirstOrder":
        time_constant = _number(dyn, "timeConstant", math.nan, source, f"{where}.dynamics")
        if not time_constant > 0:
            raise UvmsInputError("expected a <timeConstant> > 0", source, f"{where}.dynamics")
        if not linear:
            tags.notes.append(f"thruster {ident}: FirstOrder lag applied to the thrust (UUV lags the rotor "
                              "command before its Basic conversion)")
    known = ("linkName", "jointName", "thrusterID", "dynamics", "conversion", "clampMin", "clampMax",
             "thrustMin", "thrustMax", "gain", "thrust_efficiency", "propeller_efficiency", *PLUMBING,
             "thrust_topic", "thrust_ft_topic", "input_topic")
    tags.ignored.extend(f"thruster {ident}/{c.tag}" for c in plugin if c.tag not in known)
    return ThrusterTags(link, joint, ident, "ideal" if kind == "ZeroOrder" else "first_order", max_thrust,
                       time_constant)


def read_uuv_tags(text: str, source: str) -> PluginTags:
    """The UUV Simulator tags of a URDF text (already checked by :func:`uvms.model.urdf._parse`, parsed again
    here with ``defusedxml``): hydrodynamics per link, thrusters, fluid density, and what was not mapped."""
    from defusedxml.ElementTree import parse

    root = parse(io.BytesIO(text.encode("utf-8")), forbid_dtd=True).getroot()
    tags = PluginTags()
    for block in root.findall("gazebo"):
        plugins = block.findall("plugin")
        if not plugins:
            if block.get("reference") is None:
                tags.ignored.extend(f"gazebo/{c.tag}" for c in block)
            continue
        for plugin in plugins:
            filename = plugin.get("filename") or ""
            if UNDERWATER_PLUGIN in filename:
                rho = plugin.find("fluid_density")
                if rho is not None:
                    tags.fluid_density = _number(plugin, "fluid_density", 1028.0, source, "gazebo/plugin")
                    if not tags.fluid_density > 0:
                        raise UvmsInputError("expected a fluid_density > 0", source, "gazebo/plugin.fluid_density")
                for child in plugin:
                    if child.tag == "link":
                        link = _link(child, tags.fluid_density, source, tags)
                        tags.links[link.name] = link
                    elif child.tag not in ("fluid_density", *PLUMBING):
                        tags.ignored.append(f"underwater object/{child.tag}")
            elif THRUSTER_PLUGIN in filename:
                tags.thrusters.append(_thruster(plugin, source, tags))
            else:
                tags.ignored.append(f"plugin {filename or plugin.get('name') or '?'}")
    return tags
