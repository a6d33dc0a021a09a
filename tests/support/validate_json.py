#!/usr/bin/python3
"""Validate rayverify's JSON outputs against the schemas of docs/schema/.

usage: validate_json.py SCHEMA_DIR --check-schemas
       validate_json.py SCHEMA_DIR NAME FILE [--lines]

NAME is a schema file's name without .schema.json (report, per-case, ...).
With --lines, FILE is JSON Lines and every line is validated. A key the
schema does not declare, in an object whose properties it declares, is an
error too (the output drifted from its schema). Prints each error with its
path and exits 1 when there is one; exits 0 otherwise.
Run by tests/schema_test.cpp with Debian's python3-jsonschema.
"""
import json
import os
import sys

import jsonschema


def load_store(directory):
    store = {}
    for name in sorted(os.listdir(directory)):
        if name.endswith(".schema.json"):
            with open(os.path.join(directory, name)) as f:
                schema = json.load(f)
            store[name[: -len(".schema.json")]] = schema
    return store


def undeclared(value, schema, base, store, where, found):
    """Keys of an object whose schema declares its properties but not this
    one (and has no additionalProperties schema): an output that drifted
    from its schema. An object whose schema declares no properties at all
    is free-form (e.g. a shard state's internal accumulators)."""
    if not isinstance(schema, dict):
        return
    subs, i = [(schema, base)], 0
    while i < len(subs):
        s, b = subs[i]
        i += 1
        if "$ref" in s:
            target, _, fragment = s["$ref"].partition("#")
            doc = store[target[: -len(".schema.json")]] if target else b
            node = doc
            for part in fragment.strip("/").split("/"):
                if part:
                    node = node[part]
            subs.append((node, doc))
        for key in ("allOf", "anyOf", "oneOf"):
            subs.extend((x, b) for x in s.get(key, []))
    if isinstance(value, dict):
        declared, extra, shaped = {}, [], False
        for s, b in subs:
            for key, x in s.get("properties", {}).items():
                declared.setdefault(key, []).append((x, b))
                shaped = True
            if isinstance(s.get("additionalProperties"), dict):
                extra.append((s["additionalProperties"], b))
        for key, x in value.items():
            for s, b in declared.get(key, []) or extra:
                undeclared(x, s, b, store, where + "/" + key, found)
            if shaped and key not in declared and not extra:
                found.append(where + "/" + key)
    elif isinstance(value, list):
        for s, b in subs:
            if isinstance(s.get("items"), dict):
                for index, x in enumerate(value):
                    undeclared(x, s["items"], b, store, where + "/" + str(index), found)


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    store = load_store(sys.argv[1])
    if sys.argv[2] == "--check-schemas":
        for name, schema in store.items():
            jsonschema.Draft202012Validator.check_schema(schema)
            if schema.get("$id") != "https://rayverify.invalid/schema/%s.schema.json" % name:
                sys.exit("%s: $id does not name the file" % name)
        print("schemas: %d valid" % len(store))
        return
    name, path = sys.argv[2], sys.argv[3]
    lines = "--lines" in sys.argv[4:]
    schema = store[name]
    resolver = jsonschema.RefResolver.from_schema(schema, store={s["$id"]: s for s in store.values()})
    validator = jsonschema.Draft202012Validator(schema, resolver=resolver)
    with open(path) as f:
        documents = [json.loads(line) for line in f if line.strip()] if lines else [json.load(f)]
    errors = 0
    for number, document in enumerate(documents, 1):
        found = []
        undeclared(document, schema, schema, store, "", found)
        for where in sorted(set(found)):
            errors += 1
            print("%s:%s: at '%s': not declared in the schema" % (path, number if lines else 0, where))
            if errors >= 20:
                sys.exit(1)
        for error in validator.iter_errors(document):
            errors += 1
            where = "/".join(str(p) for p in error.absolute_path)
            print("%s:%s: at '%s': %s" % (path, number if lines else 0, where, error.message[:300]))
            if errors >= 20:
                sys.exit(1)
    if errors:
        sys.exit(1)
    print("valid: %d object(s) against %s" % (len(documents), name))


if __name__ == "__main__":
    main()
