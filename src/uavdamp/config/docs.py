"""The config reference, generated from the config schema: one source for every key's type, range and meaning.

`reference(schema)` renders every key of `workflow/schemas/config.schema.yaml` as Markdown tables, one per
section, with its dotted path, type, valid range and description (which carries the unit); `config/README.md`
holds the result between two markers (`update_readme`), and a test checks that it is current.
"""

from __future__ import annotations

BEGIN = "<!-- BEGIN GENERATED: config reference (uavdamp.config.docs; do not edit by hand) -->"
END = "<!-- END GENERATED: config reference -->"


def _resolve(node: dict, schema: dict) -> dict:
    """The node with its `$ref` (to `#/$defs/...`) merged in; the node's own keys win."""
    if "$ref" not in node:
        return node
    target = schema
    for part in node["$ref"].lstrip("#/").split("/"):
        target = target[part]
    return {**_resolve(target, schema), **{k: v for k, v in node.items() if k != "$ref"}}


def _range(node: dict) -> str:
    parts = []
    for key, symbol in (("minimum", ">="), ("exclusiveMinimum", ">"), ("maximum", "<="), ("exclusiveMaximum", "<")):
        if key in node:
            parts.append(f"{symbol} {node[key]:g}" if isinstance(node[key], float) else f"{symbol} {node[key]}")
    if "enum" in node:
        parts.append(" \\| ".join(str(v) for v in node["enum"]))
    if "const" in node:
        parts.append(str(node["const"]))
    if "pattern" in node:
        parts.append(f"pattern `{node['pattern']}`")
    return ", ".join(parts)


def _type(node: dict, schema: dict) -> tuple[str, str]:
    """(type text, range text) of a node; arrays show their items' type and range."""
    kind = node.get("type", "one of" if "oneOf" in node else "")
    if kind == "array":
        items = _resolve(node.get("items", {}), schema)
        size = node.get("minItems"), node.get("maxItems")
        length = f"{size[0]}" if size[0] is not None and size[0] == size[1] else ""
        return f"list{f' of {length}' if length else ''} {items.get('type', '')}".strip(), _range(items)
    return str(kind), _range(node)


def _rows(node: dict, path: str, schema: dict, rows: list) -> None:
    node = _resolve(node, schema)
    if path:
        kind, valid = _type(node, schema)
        text = " ".join(str(node.get("description", "")).split())
        rows.append((path, kind, valid, text))
    for key, child in node.get("properties", {}).items():
        _rows(child, f"{path}.{key}" if path else key, schema, rows)
    extra = node.get("additionalProperties")
    if isinstance(extra, dict):
        _rows(extra, f"{path}.NAME", schema, rows)
    items = _resolve(node.get("items", {}), schema) if node.get("type") == "array" else {}
    if "properties" in items or "oneOf" in items:
        _rows(items, f"{path}[]", schema, rows)
    for option in node.get("oneOf", []):  # the options' keys, each once (an init's const values joined)
        for key, child in _resolve(option, schema).get("properties", {}).items():
            found = [r for r in rows if r[0] == f"{path}.{key}"]
            if found and "const" in child:
                k = rows.index(found[0])
                rows[k] = (*rows[k][:2], f"{rows[k][2]} \\| {child['const']}", rows[k][3])
            elif not found:
                _rows(child, f"{path}.{key}", schema, rows)


def reference(schema: dict) -> str:
    """Markdown tables of every key of the config schema, one per top-level section."""
    out = []
    for section, node in schema["properties"].items():
        rows: list = []
        _rows(node, section, schema, rows)
        head = " ".join(str(_resolve(node, schema).get("description", "")).split())
        out += [f"### `{section}`", "", head, "", "| key | type | valid | meaning (unit) |", "|---|---|---|---|"]
        out += [f"| `{p}` | {t} | {v} | {d} |" for p, t, v, d in rows[1:]]
        out.append("")
    return "\n".join(out).rstrip() + "\n"


def update_readme(text: str, schema: dict) -> str:
    """`text` (config/README.md) with the part between BEGIN and END replaced by `reference(schema)`."""
    if BEGIN not in text or END not in text:
        raise ValueError(f"config/README.md: the markers {BEGIN!r} and {END!r} are missing")
    head, rest = text.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    return f"{head}{BEGIN}\n\n{reference(schema)}\n{END}{tail}"


if __name__ == "__main__":  # rewrite config/README.md's reference from the schema, then the docs' copy of it
    from pathlib import Path

    import yaml

    from uavdamp.results import publish

    root = Path(__file__).resolve().parents[3]
    schema = yaml.safe_load((root / "workflow" / "schemas" / "config.schema.yaml").read_text())
    readme = root / "config" / "README.md"
    readme.write_text(update_readme(readme.read_text(), schema))
    publish.refresh(root)
