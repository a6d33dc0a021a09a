#!/usr/bin/python3
"""Checks exchange files against docs/schema/rayverify-exchange-v1.json.

usage: check_exchange_schema.py SCHEMA FILE...
Each FILE is JSON lines (every line checked; the first must be a header) or
an .npy companion .json (one header object). Prints the first violation as
FILE:LINE: message and exits 1; exits 0 when every line conforms.
"""
import json
import sys

import jsonschema


def main(schema_path, files):
    schema = json.load(open(schema_path))
    validator = jsonschema.Draft7Validator(schema)
    header = schema["definitions"]["header"]
    for path in files:
        lines = open(path).read().splitlines()
        if path.endswith(".json"):
            lines = [" ".join(lines)]
        for number, line in enumerate(lines, 1):
            value = json.loads(line)
            errors = list(validator.iter_errors(value))
            if number == 1 and not errors:
                errors = list(jsonschema.Draft7Validator(header).iter_errors(value))
            if errors:
                print(f"{path}:{number}: {errors[0].message}")
                return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2:]))
