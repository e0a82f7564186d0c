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
    parameters = dict((data.get("identified") or {}).get("parameters") or {})
    parameters.update({p.name: float(v) for p, v in zip(identification.parameters, identification.values)})
    record = identification.to_dict()
    record["starting_model"] = str(base.name)
    if logs:
        record["logs"] = [str(x) for x in logs]
    return model_file_text(base, data, name, destination, parameters, record)


def model_file_text(base: Path, data: dict, name: str, destination, parameters: dict, record: dict) -> str:
    """The starting model file ``base`` (its content ``data``) as a new model file at ``destination`` named
    ``name`` with ``identified: {parameters, record}``. The starting file's text, comments (the sources of its
    numbers) included, is kept line for line, with its top-level ``name:`` and a relative ``urdf:`` line
    replaced; a file that already has an ``identified:`` block, or whose ``name:`` is not one line, is written
    from its data instead (comments lost, said in the header)."""
    import re

    urdf = data.get("urdf")
    if isinstance(urdf, str) and not os.path.isabs(urdf):
        urdf = os.path.relpath((base.parent / urdf).resolve(), Path(destination).absolute().parent)
    block = yaml.safe_dump({"identified": {"parameters": parameters, "record": record}}, sort_keys=False,
                           width=110, default_flow_style=None)
    header = (f"# {name}: {base.name} with parameters identified from logs by uvms identify\n"
              f"# (identified.record says how, on which logs, and how well; docs/logs.md, \"Identification\").\n")
    text = base.read_text(encoding="utf-8")
    lines = text.splitlines()
    names = [k for k, line in enumerate(lines) if re.match(r"name:\s*\S", line)]
    urdfs = [k for k, line in enumerate(lines) if re.match(r"urdf:\s*\S", line)]
    if "identified" not in data and len(names) == 1 and len(urdfs) == (1 if "urdf" in data else 0):
        lines[names[0]] = f"name: {yaml.safe_dump(name, default_style=None).splitlines()[0]}"
        if urdfs:
            lines[urdfs[0]] = f"urdf: {yaml.safe_dump(urdf).splitlines()[0]}"
        return header + "\n".join(lines) + "\n\n" + block
    data = {**data, "name": name, **({"urdf": urdf} if urdf is not None else {})}
    data.pop("identified", None)
    return (header + f"# (written from {base.name}'s data: its comments are in that file)\n"
            + yaml.safe_dump(data, sort_keys=False, width=110, default_flow_style=None) + block)


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
