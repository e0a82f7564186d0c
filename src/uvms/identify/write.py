"""The fitted model as a model file: the starting model's file with its ``identified:`` block set, so that the
file says what was fitted, to which logs, and how well (``docs/logs.md``, "Identification").

The file is the starting model file's content (read as data, never run) with:

- ``name`` set to the new name;
- a relative ``urdf`` path rewritten to stay valid from the new file's folder (the URDF itself is not copied);
- ``identified.parameters`` holding the fitted values (:mod:`uvms.model.parameters`; earlier identified
  values of other parameters are kept) and ``identified.record`` the fit's record
  (:meth:`~uvms.identify.fit.Identification.to_dict`).
"""

from __future__ import annotations

import os
from pathlib import Path

import yaml

from uvms.errors import UvmsInputError
from uvms.output import atomic_write_text, check_file_output, record_written
from uvms.safe_yaml import read_yaml_mapping


def fitted_model_text(identification, base_source, name: str, destination, *, logs=()) -> str:
    """The YAML text of the fitted model file that will be written at ``destination``."""
    if base_source is None:
        raise UvmsInputError("identify: the starting model has no model file to extend (load it from a file)")
    base = Path(base_source)
    if base.suffix.lower() not in (".yaml", ".yml"):
        raise UvmsInputError(f"identify: expected the starting model to come from a model YAML file, got {base}; "
                             f"write a model YAML with a urdf: key for it")
    data = read_yaml_mapping(base, "a model file")
    data["name"] = name
    if isinstance(data.get("urdf"), str) and not os.path.isabs(data["urdf"]):
        target = (base.parent / data["urdf"]).resolve()
        data["urdf"] = os.path.relpath(target, Path(destination).absolute().parent)
    identified = dict(data.get("identified") or {})
    parameters = dict(identified.get("parameters") or {})
    parameters.update({p.name: float(v) for p, v in zip(identification.parameters, identification.values)})
    record = identification.to_dict()
    record["starting_model"] = str(base.name)
    if logs:
        record["logs"] = [str(x) for x in logs]
    data["identified"] = {"parameters": parameters, "record": record}
    header = (f"# {name}: {base.name} with parameters identified from logs by uvms identify\n"
              f"# (identified.record says how, on which logs, and how well; docs/logs.md, \"Identification\").\n")
    return header + yaml.safe_dump(data, sort_keys=False, width=110, default_flow_style=None)


def write_fitted_model(identification, base_source, path, *, name: str | None = None, logs=(), named: bool = True,
                       force: bool = False) -> Path:
    """Write the fitted model file at ``path`` (never replacing a user's file unless named or forced; the
    project's output rule, :func:`uvms.output.check_file_output`) and return its path. The written file loads
    (it is checked before it is published)."""
    from uvms.model.load import load_model

    path = Path(path)
    listed = check_file_output(path, "--output", named=named, force=force)
    name = name or path.stem
    text = fitted_model_text(identification, base_source, name, path, logs=logs)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.check.yaml")
    try:
        tmp.write_text(text)
        load_model(tmp)
    finally:
        tmp.unlink(missing_ok=True)
    atomic_write_text(path, text)
    if listed:
        record_written(path)
    return path
