#!/usr/bin/python3
"""Validate rayverify's JSON outputs against the schemas of docs/schema/.

usage: validate_json.py SCHEMA_DIR --check-schemas
       validate_json.py SCHEMA_DIR NAME FILE [--lines]

NAME is a schema file's name without .schema.json (report, per-case, ...).
With --lines, FILE is JSON Lines and every line is validated. Prints each
error with its path and exits 1 when there is one; exits 0 otherwise.
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
