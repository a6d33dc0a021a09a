#!/usr/bin/python3
"""Lists the functions of src/ that nothing calls: dead code to delete.

Usage: tools/unused_functions.py BUILD_DIR

Reads the object files a complete build compiled (BUILD_DIR/compile_commands.json
names them) and prints, for each function with external linkage that a source
under src/ defines and nothing uses, `file:line: name`. Exit 0 when there is
none, 1 when there are any (or when an entry of tools/unused_functions.allow
names no unused function), 2 on a usage error or an incomplete build.

A function counts as used when
- another object file of this build refers to it: the library's, the CLI's,
  the bench library's, the tests', the tools' (an undefined symbol there);
- its own object refers to it from outside its own body (a relocation in a
  section of code or data: a call that was not inlined, a vtable, a table of
  function pointers); the library is a unity build, so a use by another file
  of the same layer is such a use;
- or its name appears, other than where a function of that name is declared
  or defined, in the sources compiled into its own object, in a header under
  src/, or in fuzz/ and tests/consumer/ (programs built outside this tree).
  This covers a use the compiler inlined everywhere, which leaves no trace in
  the object. It is text, not meaning: a namesake's call counts too, so a
  function with a common name (`write`, `name`) used nowhere may go unseen.

Out of scope: inline functions and templates defined in headers (compiled
into their users, not the library), functions with internal linkage (static
or in an anonymous namespace: the compiler's -Wunused-function covers them),
and operators, conversion functions and destructors that no other object
calls (their calls do not name them). Not reported: `main`, the plugin ABI's
entry points (`rayverify_plugin_*`), the C interface of
src/intersectors/robust_sphere_c.h (a public API for C callers), and the
functions tools/unused_functions.allow lists, each with its reason.
"""
import collections
import json
import os
import re
import shlex
import struct
import subprocess
import sys

ALLOW_LIST_NAME = "tools/unused_functions.allow"
ALLOW_LIST = os.path.join(os.path.dirname(os.path.abspath(__file__)), "unused_functions.allow")
PLUGIN_ABI_PREFIX = "rayverify_plugin_"
C_INTERFACE_HEADER = "src/intersectors/robust_sphere_c.h"
# Sources of programs that use the library but are built in trees of their own.
OUTSIDE_USER_DIRS = ["fuzz", "tests/consumer"]


def fail_usage(message):
    print(f"unused_functions: {message}", file=sys.stderr)
    sys.exit(2)


# ---- ELF object files: defined functions, undefined symbols, relocations ----

ELF_HEADER = struct.Struct("<16sHHIQQQIHHHHHH")
SECTION_HEADER = struct.Struct("<IIQQQQIIQQ")
SYMBOL = struct.Struct("<IBBHQQ")
RELOCATION = struct.Struct("<QQq")
SHT_SYMTAB, SHT_RELA, SHT_SYMTAB_SHNDX = 2, 4, 18
STT_FUNC, STB_GLOBAL, STB_WEAK = 2, 1, 2
SHN_UNDEF, SHN_XINDEX = 0, 0xFFFF
# Relocations there point at code for the debugger and the unwinder, not for a caller.
NOT_A_USE_SECTIONS = (".debug", ".eh_frame")

section_header = collections.namedtuple("section_header",
                                        "name type flags address offset size link info alignment entry_size")
# `section` is the index of the section that holds its code.
defined_function = collections.namedtuple("defined_function", "mangled section address size weak")


class object_file:
    """The symbols of one relocatable ELF64 little-endian object."""

    def __init__(self, path, with_relocations):
        self.path = path
        self.functions = []  # defined_function, global or weak
        self.undefined = set()  # mangled names this object needs from others
        self.used_here = set()  # mangled names of its own functions it refers to
        with open(path, "rb") as file:
            self.file = file
            self.read(with_relocations)
        del self.file

    def bytes_at(self, offset, size):
        self.file.seek(offset)
        return self.file.read(size)

    def contents(self, section):
        return self.bytes_at(section.offset, section.size)

    def read(self, with_relocations):
        header = ELF_HEADER.unpack(self.bytes_at(0, ELF_HEADER.size))
        ident, section_table, section_count, names_index = header[0], header[6], header[12], header[13]
        if ident[:4] != b"\x7fELF" or ident[4] != 2 or ident[5] != 1:
            fail_usage(f"{self.path}: not a 64-bit little-endian ELF object")
        first = section_header(*SECTION_HEADER.unpack(self.bytes_at(section_table, SECTION_HEADER.size)))
        # Past 0xff00 sections (a unity build's COMDAT groups) the counts live in section 0.
        if section_count == 0:
            section_count = first.size
        if names_index == SHN_XINDEX:
            names_index = first.link
        table = self.bytes_at(section_table, section_count * SECTION_HEADER.size)
        sections = [section_header(*header) for header in SECTION_HEADER.iter_unpack(table)]
        names = self.contents(sections[names_index])
        self.section_names = [c_string(names, s.name) for s in sections]

        symbol_table = next(s for s in sections if s.type == SHT_SYMTAB)
        strings = self.contents(sections[symbol_table.link])
        extended = next((s for s in sections if s.type == SHT_SYMTAB_SHNDX), None)
        extended_indices = struct.unpack(f"<{extended.size // 4}I", self.contents(extended)) if extended else ()
        function_at_index = {}
        symbols = self.contents(symbol_table)
        for index, (name, info, _, section, value, size) in enumerate(SYMBOL.iter_unpack(symbols)):
            binding, kind = info >> 4, info & 0xF
            if binding not in (STB_GLOBAL, STB_WEAK):
                continue
            if section == SHN_UNDEF:
                self.undefined.add(c_string(strings, name))
            elif kind == STT_FUNC:
                if section == SHN_XINDEX:
                    section = extended_indices[index]
                function = defined_function(c_string(strings, name), section, value, size, binding == STB_WEAK)
                self.functions.append(function)
                function_at_index[index] = function
        if with_relocations:
            self.read_uses_here(sections, function_at_index)

    def read_uses_here(self, sections, function_at_index):
        for relocations in sections:
            target = relocations.info  # the section they apply to
            if relocations.type != SHT_RELA or self.section_names[target].startswith(NOT_A_USE_SECTIONS):
                continue
            for offset, info, _ in RELOCATION.iter_unpack(self.contents(relocations)):
                function = function_at_index.get(info >> 32)
                if function is None:
                    continue
                # A recursive call is not a use.
                within_itself = function.section == target and \
                    function.address <= offset < function.address + function.size
                if not within_itself:
                    self.used_here.add(function.mangled)


def c_string(table, offset):
    return table[offset:table.index(b"\0", offset)].decode()


# ---- The build: which objects it compiled, from which sources ----

def source_dir_of(build_dir):
    cache = os.path.join(build_dir, "CMakeCache.txt")
    try:
        with open(cache, encoding="utf-8") as file:
            for line in file:
                if line.startswith("rayverify_SOURCE_DIR:"):
                    return line.split("=", 1)[1].strip()
    except OSError:
        pass
    fail_usage(f"{cache}: not a configured rayverify build directory")


def compiled_objects(build_dir):
    """(object path, the source files compiled into it) for every compile of the build."""
    path = os.path.join(build_dir, "compile_commands.json")
    try:
        with open(path, encoding="utf-8") as file:
            commands = json.load(file)
    except (OSError, ValueError) as error:
        fail_usage(f"{path}: {error} (configure with CMAKE_EXPORT_COMPILE_COMMANDS=ON)")
    objects = []
    for command in commands:
        arguments = shlex.split(command["command"])
        output = os.path.join(command["directory"], arguments[arguments.index("-o") + 1])
        if not output.endswith(".o"):  # a precompiled header
            continue
        source = command["file"]
        # A unity file is a list of #include lines, one per source.
        if "/Unity/" in source:
            with open(source, encoding="utf-8") as file:
                sources = re.findall(r'#include\s+"([^"]+)"', file.read())
        else:
            sources = [source]
        objects.append((os.path.normpath(output), [os.path.normpath(s) for s in sources]))
    missing = [output for output, _ in objects if not os.path.exists(output)]
    if missing:
        fail_usage(f"{len(missing)} object files of the build are missing ({missing[0]}, ...): "
                   f"build everything first (cmake --build {build_dir})")
    return objects


# ---- Source text: where a name is used rather than declared ----

CODE_NOISE = re.compile(r'//[^\n]*|/\*.*?\*/|R"([^(\s]*)\(.*?\)\1"|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'',
                        re.DOTALL)
ATTRIBUTES = re.compile(r"\[\[.*?\]\]|^\s*(?:public|private|protected)\s*:", re.DOTALL)
QUALIFIERS_BEFORE = re.compile(r"(?:\w+\s*::\s*)+$")
NOT_IN_A_TYPE = re.compile(r"\b(?:return|co_return|co_yield|co_await|throw|else|case|do|new|delete|goto)\b")
TYPE_CHARACTERS = re.compile(r"[\w\s:<>,*&]*")


def code_of(text):
    """The text with comments and literals blanked (line numbers kept), each
    preprocessor line ended by a ';' so that it ends a statement."""
    def blank(match):
        return re.sub(r"[^\n]", " ", match.group(0)) if match.group(0).startswith("/") else '""'
    code = CODE_NOISE.sub(blank, text)
    return re.sub(r"^(\s*#.*)$", r"\1;", code, flags=re.MULTILINE)


def declares(code, start, end):
    """Whether the name at code[start:end] is declared or defined there: followed by
    its parameters and preceded, within its statement, by a return type alone."""
    after = code[end:end + 200].lstrip()
    if after.startswith("<"):  # explicit template arguments
        depth = 0
        for i, character in enumerate(after):
            depth += {"<": 1, ">": -1}.get(character, 0)
            if depth == 0:
                after = after[i + 1:].lstrip()
                break
    if not after.startswith("("):
        return False
    before = code[max(0, start - 400):start]
    qualifiers = QUALIFIERS_BEFORE.search(before)
    if qualifiers:
        before = before[:qualifiers.start()]
    statement_start = max(before.rfind(";"), before.rfind("{"), before.rfind("}"))
    prefix = ATTRIBUTES.sub(" ", before[statement_start + 1:]).strip()
    if not prefix or not prefix[0].isalpha() and prefix[0] != "_":
        return False
    if not TYPE_CHARACTERS.fullmatch(prefix) or NOT_IN_A_TYPE.search(prefix) or "<<" in prefix:
        return False
    if ":" in prefix.replace("::", ""):
        return False
    # Commas only between template arguments: `{a, name(x)}` is a use.
    depth = 0
    for character in prefix:
        depth += {"<": 1, ">": -1}.get(character, 0)
        if character == "," and depth <= 0:
            return False
    return True


class source_text:
    """Files read once, comments and literals blanked."""

    def __init__(self):
        self.code = {}

    def of(self, path):
        if path not in self.code:
            try:
                with open(path, encoding="utf-8", errors="replace") as file:
                    self.code[path] = code_of(file.read())
            except OSError:
                self.code[path] = ""
        return self.code[path]

    def names_used(self, names, paths):
        """The names among `names` that some file of `paths` uses, not just declares."""
        if not names:
            return set()
        pattern = re.compile(r"\b(?:" + "|".join(map(re.escape, sorted(names))) + r")\b")
        used = set()
        for path in paths:
            code = self.of(path)
            for match in pattern.finditer(code):
                if match.group(0) not in used and not declares(code, match.start(), match.end()):
                    used.add(match.group(0))
        return used

    def definition_line(self, name, paths):
        """Where a function `name` is defined among `paths` (a build without debug information)."""
        pattern = re.compile(r"\b" + re.escape(name) + r"\b")
        for path in paths:
            code = self.of(path)
            for match in pattern.finditer(code):
                if declares(code, match.start(), match.end()):
                    return path, code.count("\n", 0, match.start()) + 1
        return None


# ---- Names ----

def demangled(names):
    if not names:
        return {}
    result = subprocess.run(["c++filt"], input="\n".join(names) + "\n", capture_output=True, text=True,
                            check=True)
    return dict(zip(names, result.stdout.splitlines()))


def qualified_name(signature):
    """`ns::type::name` of a demangled signature: no return type, template
    arguments, ABI tags, parameters, qualifiers or compiler-made parts (a
    `[clone .resolver]` of a function built for several targets, which
    clang makes global even for a function in an anonymous namespace, is
    the function's own)."""
    signature = re.sub(r"(?:\s*\[clone [^\]]*\])+$", "", signature)
    signature = re.sub(r"(?:\s*(?:const|volatile|&&|&))+$", "", signature)
    name = re.sub(r"\[abi:\w+\]", "", signature[:last_balanced(signature, "(", ")")])
    operator = re.search(r"\boperator\b", name)
    if operator:  # `operator<`, `operator std::string`: the rest is the name
        name, tail = name[:operator.start()], name[operator.start():]
    else:
        name, tail = name[:last_balanced(name, "<", ">")], ""
    # A template's demangled name starts with its return type.
    depth = 0
    for i in range(len(name) - 1, -1, -1):
        depth += {">": 1, "<": -1, ")": 1, "(": -1}.get(name[i], 0)
        if name[i] == " " and depth == 0:
            return name[i + 1:] + tail
    return name + tail


def last_balanced(text, opening, closing):
    """Where the bracketed group that ends `text` starts (len(text) when none does)."""
    depth = 0
    for i in range(len(text) - 1, -1, -1):
        if i == len(text) - 1 and text[i] != closing:
            return len(text)
        depth += {closing: 1, opening: -1}.get(text[i], 0)
        if depth == 0:
            return i
    return len(text)


def short_name(name):
    return name.rsplit("::", 1)[-1]


def internal_linkage(name):
    """A function in an anonymous namespace, out of scope like a static one
    (its resolver symbol may still be global)."""
    return "(anonymous namespace)::" in name


def implicitly_called(name):
    """Operators, conversion functions and destructors: their calls do not name them."""
    return re.search(r"(?:^|::)(?:~|operator\b)", name) is not None


# ---- Where a function is defined ----

def definition_lines(obj, functions):
    """{mangled: (path as the debug information names it, line)} from the
    object's debug information (empty for a build without it)."""
    by_section = {}
    for function in functions:
        by_section.setdefault(obj.section_names[function.section], []).append(function)
    lines = {}
    for section_name, in_section in by_section.items():
        result = subprocess.run(["addr2line", "-e", obj.path, "-j", section_name]
                                + [hex(f.address) for f in in_section], capture_output=True, text=True)
        for function, line in zip(in_section, result.stdout.splitlines()):
            path, _, number = line.split(" ")[0].rpartition(":")
            if path != "??" and number.isdigit() and int(number) > 0:
                lines[function.mangled] = (path, int(number))
    return lines


def in_source_tree(path, source_dir):
    """A path from debug information, of this or another checkout (the compiler
    cache may have built the object elsewhere), as the path under source_dir/src."""
    parts = os.path.normpath(path).split(os.sep)
    for i in range(len(parts) - 1, -1, -1):
        if parts[i] == "src":
            in_tree = os.path.join(source_dir, *parts[i:])
            if os.path.exists(in_tree):
                return in_tree
    return None


# ---- What is not reported ----

def c_interface_names(source_dir):
    with open(os.path.join(source_dir, C_INTERFACE_HEADER), encoding="utf-8") as file:
        return set(re.findall(r"\b(\w+)\s*\(", code_of(file.read())))


def read_allow_list():
    """{qualified name: reason} from tools/unused_functions.allow."""
    allowed = {}
    try:
        with open(ALLOW_LIST, encoding="utf-8") as file:
            for number, line in enumerate(file, 1):
                line = line.strip()
                if not line or line.startswith("#"):
                    continue
                name, _, reason = line.partition(" ")
                if not reason.strip():
                    fail_usage(f"{ALLOW_LIST}:{number}: {name} needs a reason after the name")
                allowed[name] = reason.strip()
    except FileNotFoundError:
        pass
    return allowed


def source_files(root, directories, suffixes):
    found = []
    for directory in directories:
        for parent, _, names in os.walk(os.path.join(root, directory)):
            found += [os.path.join(parent, n) for n in names if n.endswith(suffixes)]
    return sorted(found)


# ---- The check ----

# A function of ours, with the object that defines it and the sources under src/ compiled into that object.
candidate = collections.namedtuple("candidate", "obj sources function name")


def unreferenced_functions(objects, src):
    """A candidate for each function of ours that no object refers to; aliases
    (one address: a constructor's C1 and C2) are one function."""
    read = {}
    undefined_anywhere = set()
    for output, sources in objects:
        read[output] = object_file(output, with_relocations=any(s.startswith(src) for s in sources))
        undefined_anywhere |= read[output].undefined
    unreferenced = []
    for output, sources in objects:
        obj, ours = read[output], [s for s in sources if s.startswith(src)]
        at_address = {}
        for function in obj.functions if ours else []:
            at_address.setdefault((function.section, function.address), []).append(function)
        for aliases in at_address.values():
            if not any(f.mangled in undefined_anywhere or f.mangled in obj.used_here for f in aliases):
                unreferenced.append(candidate(obj, ours, min(aliases, key=lambda f: f.mangled), None))
    return unreferenced


def located(candidates, source_dir, text):
    """(file, line, name) of each candidate defined in a .cpp file, from the
    debug information or else the source text; those defined in a header
    (inline functions, templates) are left out."""
    found = []
    for obj in {c.obj for c in candidates}:
        in_object = [c for c in candidates if c.obj is obj]
        own_cpp = [s for s in in_object[0].sources if s.endswith(".cpp")]
        in_text = {c.function.mangled: text.definition_line(short_name(c.name), own_cpp) for c in in_object}
        # A weak function that no own .cpp file defines is an inline function or a template of a header.
        in_object = [c for c in in_object if in_text[c.function.mangled] or not c.function.weak]
        debug_lines = definition_lines(obj, [c.function for c in in_object])
        for c in in_object:
            if c.function.mangled in debug_lines:
                path, line = debug_lines[c.function.mangled]
                path = in_source_tree(path, source_dir)  # None outside src/
                where = (path, line) if path else None
            else:
                where = in_text[c.function.mangled] or (obj.path, 0)
            if where and (where[0].endswith(".cpp") or where[0] == obj.path):
                found.append((os.path.relpath(where[0], source_dir), where[1], c.name))
    return found


def unused_functions(build_dir):
    """The (file, line, name) of each unused function, and the allow-list's entries
    that name none."""
    source_dir = source_dir_of(build_dir)
    unreferenced = unreferenced_functions(compiled_objects(build_dir), os.path.join(source_dir, "src") + os.sep)
    signatures = demangled([c.function.mangled for c in unreferenced])
    excluded = c_interface_names(source_dir) | {"main"}
    by_object = {}
    for c in unreferenced:
        name = qualified_name(signatures[c.function.mangled])
        if name not in excluded and not name.startswith(PLUGIN_ABI_PREFIX) and not implicitly_called(name) \
                and not internal_linkage(name):
            by_object.setdefault(c.obj, []).append(c._replace(name=name))

    text = source_text()
    elsewhere = source_files(source_dir, ["src"], (".h",)) + \
        source_files(source_dir, OUTSIDE_USER_DIRS, (".h", ".cpp", ".c"))
    not_named = []
    for in_object in by_object.values():
        used = text.names_used({short_name(c.name) for c in in_object}, in_object[0].sources + elsewhere)
        not_named += [c for c in in_object if short_name(c.name) not in used]

    allowed = read_allow_list()
    found = located(not_named, source_dir, text)
    unused = sorted({u for u in found if u[2] not in allowed})
    return unused, sorted(set(allowed) - {u[2] for u in found})


def main():
    if len(sys.argv) != 2 or sys.argv[1].startswith("-"):
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    unused, stale = unused_functions(os.path.abspath(sys.argv[1]))
    for path, line, name in unused:
        print(f"{path}:{line}: {name}")
    for name in stale:
        print(f"{ALLOW_LIST_NAME}: {name} is allowed but not an unused function: "
              "take it off the list")
    if unused:
        print(f"{len(unused)} unused function(s): delete them, or list deliberate API in "
              f"{ALLOW_LIST_NAME} with the reason", file=sys.stderr)
    sys.exit(1 if unused or stale else 0)


if __name__ == "__main__":
    main()
