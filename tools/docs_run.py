#!/usr/bin/python3
"""Run every rayverify command line of README.md and docs/*.md and check what it prints.

    tools/docs_run.py --binary build/rayverify [--repo DIR] [--jobs N] [--only FILE ...]
    tools/docs_run.py --binary build/rayverify --regenerate   # rewrite literal blocks that differ
    tools/docs_run.py --self-test --binary build/rayverify     # the checker must catch broken docs
    tools/docs_run.py --binary build/rayverify --only-marked "figures vary" "depends on the CPU"
                                                             # only the blocks that carry one of these markers

The rules (docs/testing.md, "Documented commands"):

- A fenced block tagged sh/bash, or untagged, whose lines run rayverify is run in
  a scratch directory made for its document (a unique temporary directory holding
  a copy of corpus/, examples/, src/plugin/ and tests/plugin_fixtures/, with
  build/rayverify and `rayverify` first on PATH, then Debian's /usr/bin; RV names the repository). Blocks of one
  document run in order in the same directory, so a file one block makes is there
  for the next.
- In an untagged block, lines starting `$ ` are commands and the lines after one are
  what it prints (stdout and stderr together); they must match the regenerated
  output after the normalisation below, whole, unless the block is an excerpt.
- Every command exits 0 unless a `<!-- docs-run: exit N ... -->` marker says
  otherwise (one status for all, or one per command in order).
- Markers are HTML comments on the lines just above the fence, one directive each:
    <!-- docs-run: excerpt -->        the block's lines appear in this order in the output
                                       (`...` and `…` lines stand for what is left out)
    <!-- docs-run: exit 1 -->         expected exit status(es)
    <!-- docs-run: output of CMD -->  an untagged block without `$ ` lines is CMD's output
    <!-- docs-run: setup CMD -->      a shell command run first, in the scratch directory
    <!-- docs-run: shortened A -> B (WHY) -->  run with A replaced by B (a shorter run)
    <!-- docs-run: adapted A -> B (WHY) -->    run with A replaced by B (paths of the scratch directory)
    <!-- docs-run: figures vary (WHY) -->      measurements: every number compares as `#`, whether a
                                               time target was met, what a missed one needs (the lines
                                               indented under its met/MISSED line) and which variant is
                                               recommended or runner-up (the cheapest that meets a budget)
                                               not at all
    <!-- docs-run: depends on the CPU: NAME ... (WHY) -->  lines naming one of these targets (a library
                                               whose answers depend on the CPU: `rayverify engines` says
                                               which) compare up to the name only; a block that audits
                                               such a library (--engine NAME) without this marker fails
    <!-- docs-run: rows in any order (WHY) --> an excerpt whose lines may come in any order
    <!-- docs-run: needs engine NAME | needs program NAME | needs python module NAME -->
                                       skipped, saying so, where this machine lacks it
    <!-- docs-run: skip WHY -->         not run (a GPU, Slurm, a synopsis, ...)
    <!-- docs-run: not output (WHAT) -->  an untagged block that is a file's text, not output
- Normalisation, applied to the documented and the regenerated text alike: the scratch
  directory becomes `<scratch>`, the repository `<repo>`; a `build: ...` line's compiler and flags `<build>`;
  durations in seconds (`0.353 s`) `<s> s`; ISO dates `<date>`; process ids `<pid>`; a
  `rayverify builds` cache entry's 16 hex digits `<entry>`;
  trailing blanks go.
Exit status 0 when every block passes, 1 when one does not (each failure explained),
2 for a usage error.
"""
import argparse
import concurrent.futures
import difflib
import glob
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

MARKER = re.compile(r"^\s*<!--\s*docs-run:\s*(.*?)\s*-->\s*$")
FENCE = re.compile(r"^(\s*)```(\S*)\s*$")
RUNS_RAYVERIFY = re.compile(r"(^|[\s/;|(&])rayverify\s+[a-z-]")
SHELL_TAGS = {"sh", "bash", "shell"}
OUTPUT_TAGS = {"", "console"}
COPIED_PATHS = ["corpus", "examples", "src/plugin", "tests/plugin_fixtures"]
COMMAND_TIMEOUT_S = 120
DIRECTIVES = ("excerpt", "exit", "output of", "setup", "shortened", "adapted", "figures vary", "rows in any order",
              "needs", "skip", "not output", "depends on the CPU:")


class Block:
    """One fenced block of a document, with the markers above it."""

    def __init__(self, path, line, tag, body, markers):
        self.path, self.line, self.tag, self.body, self.markers = path, line, tag, body, markers
        self.body_start = line  # index (0-based) of the first body line in the file

    def where(self):
        return f"{self.path}:{self.line}"

    def directive(self, name):
        return [m[len(name):].strip() for m in self.markers if m.startswith(name)]


def read_blocks(path):
    """Every fenced block of a Markdown file."""
    lines = open(path, encoding="utf-8").read().split("\n")
    blocks, i = [], 0
    while i < len(lines):
        fence = FENCE.match(lines[i])
        if not fence:
            i += 1
            continue
        end = i + 1
        while end < len(lines) and not lines[end].strip().startswith("```"):
            end += 1
        markers, k = [], i - 1
        while k >= 0 and MARKER.match(lines[k]):
            markers.insert(0, MARKER.match(lines[k]).group(1))
            k -= 1
        indent = len(fence.group(1))
        body = [l[indent:] if l[:indent].strip() == "" else l for l in lines[i + 1:end]]
        blocks.append(Block(path, i + 1, fence.group(2), body, markers))
        i = end + 1
    return blocks


def join_continuations(lines):
    """Shell lines with a trailing backslash joined to the next."""
    joined, pending = [], ""
    for line in lines:
        if line.endswith("\\"):
            pending += line[:-1] + " "
        else:
            joined.append(pending + line)
            pending = ""
    if pending:
        joined.append(pending)
    return joined


def session(block):
    """[(command, [expected output lines])] of an untagged block; None when it shows no `$ ` line."""
    if block.tag in SHELL_TAGS:
        commands = [l for l in join_continuations(block.body) if l.strip() and not l.lstrip().startswith("#")]
        return [(c, None) for c in commands]
    outputs = block.directive("output of")
    if outputs:
        return [(outputs[0], list(block.body))]
    if not block.body or not block.body[0].startswith("$ "):
        return None
    steps, i = [], 0
    while i < len(block.body):
        command_lines = [block.body[i][2:]]
        while command_lines[-1].endswith("\\") and i + 1 < len(block.body):
            i += 1
            command_lines.append(block.body[i])
        i += 1
        output = []
        while i < len(block.body) and not block.body[i].startswith("$ "):
            output.append(block.body[i])
            i += 1
        steps.append((" ".join(l[:-1] if l.endswith("\\") else l for l in command_lines), output))
    return steps


def is_runnable(block):
    if block.tag not in SHELL_TAGS | OUTPUT_TAGS:
        return False
    steps = session(block)
    return steps is not None and any(RUNS_RAYVERIFY.search(c) for c, _ in steps)


def classify(block):
    """'run', 'skip' (with a reason), 'text' (not output) or 'unmarked' (an output block with no command)."""
    if block.directive("skip"):
        return "skip"
    if is_runnable(block):
        return "run"
    if block.tag in OUTPUT_TAGS and not block.directive("not output"):
        return "unmarked"
    return "text"


BUILD_LINE = re.compile(r"^(\s*)build: .*$")
SECONDS = re.compile(r"\b\d+(\.\d+)? s\b")
ISO_DATE = re.compile(r"\b\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d(\.\d+)?Z\b")
PID = re.compile(r"\bpid \d+\b")
# A `rayverify builds` cache entry (16 hex digits of the build's key, which
# covers the content of rayverify's own headers: it changes with them).
BUILD_ENTRY = re.compile(r"\b[0-9a-f]{16}/plugin\.so\b")
BASH_JOB = re.compile(r"^bash: line \d+: +\d+ ")
TARGET_MET = re.compile(r"\b(met|missed|MISSED)\b")
RUNNER_UP = re.compile(r"\s*<- (runner-up|recommended)$")
TIMED_CHOICE = re.compile(r"(recommended for [a-z]+ rays: )\S+")
NUMBER = re.compile(r"[-+]?(\d+(\.\d*)?|\.\d+)([eE][-+]?\d+)?")


CPU_DEPENDENT_NAMES = re.compile(r"^(.*?)\s*\(.*\)\s*$")


def cpu_dependent_names(block):
    """The target names a `depends on the CPU: NAME ... (WHY)` marker lists."""
    names = []
    for marker in block.directive("depends on the CPU:"):
        match = CPU_DEPENDENT_NAMES.match(marker)
        names += (match.group(1) if match else marker).split()
    return names


def cut_at_cpu_dependent_name(line, names):
    """A line that names one of `names` as a word, kept up to that name: the rest depends on the CPU."""
    for name in names:
        match = re.search(r"(?<![\w.-])" + re.escape(name) + r"(?![\w-])", line)
        if match:
            return line[:match.end()] + " <depends on the CPU>"
    return line


def normalise(line, scratch, repo, figures_vary):
    line = line.replace(scratch, "<scratch>").replace(repo, "<repo>").rstrip()
    line = BUILD_LINE.sub(r"\1build: <build>", line)
    line = ISO_DATE.sub("<date>", line)
    line = SECONDS.sub("<s> s", line)
    line = PID.sub("pid <pid>", line)
    line = BUILD_ENTRY.sub("<entry>/plugin.so", line)
    line = BASH_JOB.sub("bash: line <n>: <pid> ", line)
    if figures_vary:
        line = RUNNER_UP.sub("", TARGET_MET.sub("<met or missed>", line))
        line = TIMED_CHOICE.sub(r"\1<the cheapest>", line)
        line = re.sub(r"\s+", " ", NUMBER.sub("#", line)).strip()
    return line


TARGET_VERDICT = re.compile(r"\b(met|missed|MISSED)\s*$")


def indentation(line):
    return len(line) - len(line.lstrip(" "))


def without_missed_reasons(lines):
    """The lines less those indented under a met/MISSED target line: what a missed target would need,
    printed only when it is missed."""
    kept, under = [], None
    for line in lines:
        if under is not None and line.strip() and indentation(line) > under:
            continue
        under = indentation(line) if TARGET_VERDICT.search(line) else None
        kept.append(line)
    return kept


def normalise_all(lines, scratch, repo, figures_vary, cpu_names=()):
    if figures_vary:
        lines = without_missed_reasons(lines)
    if cpu_names:
        lines = [cut_at_cpu_dependent_name(line, cpu_names) for line in lines]
    normalised = (normalise(line, scratch, repo, figures_vary) for line in lines)
    return [line for line in normalised if line is not None]


GAP = {"...", "…"}


def compare(expected, actual, excerpt, any_order=False):
    """None when the documented lines match the regenerated ones, else a reason with a diff."""
    while expected and not expected[-1].strip():
        expected = expected[:-1]
    while actual and not actual[-1].strip():
        actual = actual[:-1]
    if not excerpt:
        if expected == actual:
            return None
        diff = difflib.unified_diff(expected, actual, "documented", "regenerated", lineterm="", n=1)
        return "output differs (mark the block <!-- docs-run: excerpt --> only if it shows part of it):\n" + \
            "\n".join(diff)
    position = 0
    for line in expected:
        if line.strip() in GAP:
            continue
        if any_order:
            position = 0
        while position < len(actual) and actual[position] != line:
            position += 1
        if position == len(actual):
            return f"excerpt line not found in the output, in order:\n  {line}\noutput:\n" + \
                "\n".join("  " + l for l in actual)
        position += 1
    return None


def expected_statuses(block, count):
    exits = block.directive("exit")
    if not exits:
        return [0] * count
    values = [int(v) for v in exits[0].split()]
    return values * count if len(values) == 1 else values


def unmet_need(block, context):
    for need in block.directive("needs"):
        kind, _, names = need.partition(" ")
        if kind == "engine":
            for name in names.split():
                if name not in context.available_engines():
                    return f"engine {name} is not available on this machine"
        elif kind == "program":
            for name in names.split():
                if shutil.which(name) is None:
                    return f"program {name} is not installed"
        elif kind == "python":
            module = names.split()[-1]
            probe = subprocess.run(["/usr/bin/python3", "-c", f"import {module}"], capture_output=True)
            if probe.returncode != 0:
                return f"python module {module} is not installed"
        else:
            return f"unknown need '{need}'"
    return None


ENGINES_COUNT_LINE = re.compile(r"^\d+ of \d+ engine ")
CPU_DEPENDENCE_LINE = re.compile(r"^answers depend on the CPU: (.*?): ")


class Context:
    """The binary, the repository, and what this machine offers."""

    def __init__(self, binary, repo, only_marked=()):
        self.binary, self.repo = os.path.abspath(binary), os.path.abspath(repo)
        self.only_marked = tuple(only_marked)
        self._engines = None
        self._cpu_dependent = None

    def _read_engines(self):
        """`rayverify engines`: its rows until the count line, then which targets depend on the CPU."""
        listing = subprocess.run([self.binary, "engines"], capture_output=True, text=True).stdout.splitlines()
        self._engines, self._cpu_dependent = set(), set()
        rows = True
        for line in listing[1:]:
            if ENGINES_COUNT_LINE.match(line):
                rows = False
            elif rows and line.strip() and " available" in line and "not available" not in line:
                self._engines.add(line.split()[0])
            elif not rows and CPU_DEPENDENCE_LINE.match(line):
                self._cpu_dependent.update(n.strip() for n in CPU_DEPENDENCE_LINE.match(line).group(1).split(","))

    def available_engines(self):
        if self._engines is None:
            self._read_engines()
        return self._engines

    def cpu_dependent_engines(self):
        """The targets whose answers depend on the CPU, as `rayverify engines` says."""
        if self._cpu_dependent is None:
            self._read_engines()
        return self._cpu_dependent


ENGINE_OPTION = re.compile(r"--engine[ =]'?\"?([\w.-]+):kernels")


def unmarked_cpu_dependence(block, steps, context):
    """A reason when the block runs or shows a target whose answers depend on the CPU that its
    `depends on the CPU:` marker does not name (a word of a command or of its documented output); None otherwise."""
    marked = set(cpu_dependent_names(block))
    for command, expected in steps:
        text = "\n".join([command] + (expected or []))
        named = {n for n in context.cpu_dependent_engines()
                 if re.search(r"(?<![\w.-])" + re.escape(n) + r"(?![\w-]|:kernels)", text)}
        named |= {m + ":kernels" for m in ENGINE_OPTION.findall(command)}
        missing = sorted(named - marked)
        if missing:
            return (f"`{command}` runs or shows {', '.join(missing)}, whose answers depend on the CPU (`rayverify "
                    f"engines` says why): mark the block <!-- docs-run: depends on the CPU: {' '.join(missing)} (WHY) "
                    "--> so that their lines are compared up to the name only")
    return None


def make_scratch(context, parent):
    scratch = tempfile.mkdtemp(prefix="docs-run-", dir=parent)
    for relative in COPIED_PATHS:
        source = os.path.join(context.repo, relative)
        if os.path.isdir(source):
            shutil.copytree(source, os.path.join(scratch, relative), symlinks=True)
    os.makedirs(os.path.join(scratch, "build"))
    os.symlink(context.binary, os.path.join(scratch, "build", "rayverify"))
    bin_dir = os.path.join(scratch, ".docs-run-bin")
    os.makedirs(bin_dir)
    os.symlink(context.binary, os.path.join(bin_dir, "rayverify"))
    return scratch, bin_dir


def run_steps(commands, scratch, bin_dir, context):
    """Each command's output and exit status, all in one shell so that `echo $?` sees the last."""
    separator = "@@docs-run-%s@@" % os.urandom(6).hex()
    script = ["exec 2>&1", "set +e"]
    for index, command in enumerate(commands):
        script += [f"__docs_run_status=$?; printf '\\n{separator} begin {index}\\n'; (exit $__docs_run_status)",
                   command,
                   f"__docs_run_status=$?; printf '\\n{separator} end %d\\n' $__docs_run_status; "
                   f"(exit $__docs_run_status)"]
    environment = dict(os.environ, PATH=os.pathsep.join([bin_dir, "/usr/bin", os.environ.get("PATH", "")]), RV=context.repo,
                       NO_COLOR="1", TZ="UTC", LC_ALL="C.UTF-8")
    environment.pop("COLUMNS", None)
    try:
        result = subprocess.run(["/bin/bash", "-c", "\n".join(script)], cwd=scratch, env=environment,
                                stdin=subprocess.DEVNULL, capture_output=True, timeout=COMMAND_TIMEOUT_S)
        text = result.stdout.decode("utf-8", "replace")
    except subprocess.TimeoutExpired as timeout:
        text = (timeout.stdout or b"").decode("utf-8", "replace") + f"\n(timed out after {COMMAND_TIMEOUT_S} s)"
    outputs = []
    for index in range(len(commands)):
        match = re.search(re.escape(f"{separator} begin {index}") + r"\n(.*?)\n" +
                          re.escape(separator) + r" end (\d+)\n", text, re.S)
        if match is None:
            tail = text.split(f"{separator} begin {index}\n", 1)[-1]
            outputs.append((tail.split("\n"), None))
        else:
            outputs.append((match.group(1).split("\n"), int(match.group(2))))
    return outputs


def check_document(path, context, parent, regenerate):
    """(passed, skipped, failures, replacements) for one Markdown file."""
    started = time.monotonic()
    blocks = read_blocks(os.path.join(context.repo, path))
    scratch, bin_dir = make_scratch(context, parent)
    passed, skipped, failures, replacements = 0, [], [], []
    for block in blocks:
        block.path = path
        unknown = [m for m in block.markers if not m.startswith(DIRECTIVES)]
        if unknown:
            failures.append(f"{block.where()}: unknown marker(s) {unknown}: docs/testing.md lists them")
            continue
        kind = classify(block)
        if kind == "text":
            continue
        if context.only_marked and not any(block.directive(marker) for marker in context.only_marked):
            continue
        if kind == "unmarked":
            failures.append(f"{block.where()}: an untagged block that runs no rayverify command line: start it with "
                            "`$ COMMAND`, or mark it (output of, not output, skip)")
            continue
        if kind == "skip":
            skipped.append(f"{block.where()}: skipped: {block.directive('skip')[0]}")
            continue
        reason = unmet_need(block, context)
        if reason:
            skipped.append(f"{block.where()}: skipped: {reason}")
            continue
        steps = session(block)
        commands = [c for c, _ in steps]
        for shortening in block.directive("shortened") + block.directive("adapted"):
            match = re.match(r"(.+?) -> (.+?) \((.+)\)$", shortening)
            if match is None:
                failures.append(f"{block.where()}: marker '{shortening}' is not 'A -> B (WHY)'")
                continue
            commands = [c.replace(match.group(1), match.group(2)) for c in commands]
        unmarked = unmarked_cpu_dependence(block, list(zip(commands, [e for _, e in steps])), context)
        if unmarked:
            failures.append(f"{block.where()}: {unmarked}")
            continue
        setups = block.directive("setup")
        results = run_steps(setups + commands, scratch, bin_dir, context)
        problems = [f"setup `{command}` exited {status}; it printed:\n" + "\n".join("  " + l for l in output[-20:])
                    for command, (output, status) in zip(setups, results) if status != 0]
        results = results[len(setups):]
        statuses = expected_statuses(block, len(commands))
        excerpt = bool(block.directive("excerpt"))
        figures_vary = bool(block.directive("figures vary"))
        cpu_names = cpu_dependent_names(block)
        any_order = bool(block.directive("rows in any order"))
        for index, ((command, expected), (output, status)) in enumerate(zip(steps, results)):
            want = statuses[index] if index < len(statuses) else 0
            if status != want:
                problems.append(f"`{command}` exited {status}, the docs say {want}; it printed:\n" +
                                "\n".join("  " + l for l in output[-20:]))
            if expected is None:
                continue
            documented = normalise_all(expected, scratch, context.repo, figures_vary, cpu_names)
            regenerated = normalise_all(output, scratch, context.repo, figures_vary, cpu_names)
            problem = compare(documented, regenerated, excerpt or any_order, any_order)
            if problem:
                problems.append(f"`{command}`: {problem}")
                if regenerate and not excerpt and not figures_vary and not cpu_names:
                    # The repository as the documents name it (<repo>): every clone prints its own path.
                    replacements.append((block, index, [l.replace(scratch, ".").replace(context.repo, "<repo>").rstrip()
                                                        for l in output]))
        if problems:
            failures.append(f"{block.where()}:\n" + "\n".join(problems))
        else:
            passed += 1
    shutil.rmtree(scratch, ignore_errors=True)
    print(f"docs-run: {path}: {time.monotonic() - started:.1f} s", flush=True)
    return passed, skipped, failures, replacements


def apply_replacements(repo, replacements):
    """Rewrite documented outputs with the regenerated ones (blocks of one file, last first)."""
    by_file = {}
    for block, index, output in replacements:
        by_file.setdefault(block.path, []).append((block, index, output))
    for path, items in by_file.items():
        full = os.path.join(repo, path)
        lines = open(full, encoding="utf-8").read().split("\n")
        for block, index, output in sorted(items, key=lambda item: (item[0].line, item[1]), reverse=True):
            while output and not output[-1].strip():
                output = output[:-1]
            if block.directive("output of"):
                start, end = block.body_start, block.body_start + len(block.body)
            else:
                starts = [k for k, l in enumerate(block.body) if l.startswith("$ ")]
                first = starts[index] + 1
                while block.body[first - 1].endswith("\\"):
                    first += 1
                last = starts[index + 1] if index + 1 < len(starts) else len(block.body)
                start, end = block.body_start + first, block.body_start + last
            lines[start:end] = output
        open(full, "w", encoding="utf-8").write("\n".join(lines))
        print(f"docs-run: rewrote outputs in {path}")


def documents(repo, only):
    if only:
        return only
    return ["README.md"] + sorted(os.path.relpath(p, repo) for p in glob.glob(os.path.join(repo, "docs", "*.md")))


def run_all(context, paths, jobs, regenerate):
    parent = tempfile.mkdtemp(prefix="rayverify-docs-run-")
    try:
        # The documents that draw plots or time things take longest: started first, they
        # overlap with the rest instead of running alone at the end.
        def cost(path):
            text = open(os.path.join(context.repo, path), encoding="utf-8").read()
            return text.count("--plots") * 10 + text.count("figures vary")
        with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
            futures = {path: pool.submit(check_document, path, context, parent, regenerate)
                       for path in sorted(paths, key=cost, reverse=True)}
            results = [(path, futures[path].result()) for path in paths]
    finally:
        shutil.rmtree(parent, ignore_errors=True)
    total_passed, total_failures, all_replacements = 0, 0, []
    for path, (passed, skipped, failures, replacements) in results:
        total_passed += passed
        total_failures += len(failures)
        all_replacements += replacements
        for line in skipped:
            print(line)
        for failure in failures:
            print(f"FAILED {failure}\n")
    if regenerate and all_replacements:
        apply_replacements(context.repo, all_replacements)
    print(f"docs-run: {total_passed} blocks ran as documented, {total_failures} did not, in {len(paths)} documents")
    return 0 if total_failures == 0 else 1


def self_test(context):
    """The checker passes a right document and fails each kind of wrong one."""
    right = ("<!-- docs-run: exit 1 -->\n```\n$ rayverify audit --variant naive --precision float --summary "
             "--generate near_tangent:50\n" + "{output}```\n\n```sh\nrayverify variants --json > v.json\n```\n")
    probe = subprocess.run([context.binary, "audit", "--variant", "naive", "--precision", "float", "--summary",
                            "--generate", "near_tangent:50"], capture_output=True, text=True)
    output = probe.stdout + probe.stderr
    cases = {
        "right": (right.format(output=output), 0),
        "a changed figure": (right.format(output=output.replace("naive", "naive ", 1)), 1),
        "a wrong exit status": (right.replace("exit 1", "exit 0").format(output=output), 1),
        "a command that no longer parses": (right.format(output=output).replace("variants --json",
                                                                                  "variants --jsonn"), 1),
        "an output block with no command": ("```\nsome output\n```\n", 1),
        "an excerpt that is not in the output": ("<!-- docs-run: excerpt -->\n```\n$ rayverify variants\n"
                                                  "no such line\n```\n", 1),
        "a misspelt marker": ("<!-- docs-run: excerp -->\n```\n$ rayverify variants --json > /dev/null\n```\n", 1),
    }
    # A row of a target whose answers depend on the CPU, documented with other figures and another verdict than
    # this machine prints (as another CPU's kernel gives): it passes when the block is marked, and only then.
    cpu_probe = subprocess.run([context.binary, "audit", "--variant", "naive", "--variant", "half_b", "--precision",
                                "float", "--summary", "--generate", "near_tangent:50"], capture_output=True, text=True)
    cpu_output = cpu_probe.stdout + cpu_probe.stderr
    half_b_row = next((l for l in cpu_output.splitlines() if l.startswith("half_b")), "")
    other_cpu_row = re.sub(r"[a-z_]+ \d+\b", "wrong_root 112", re.sub(r"\d", "7", half_b_row.split("half_b", 2)[-1]))
    other_cpu_output = cpu_output.replace(half_b_row, half_b_row.split("half_b", 2)[0] + "half_b" + other_cpu_row)
    cpu_block = ("{marker}<!-- docs-run: exit 1 -->\n```\n$ rayverify audit --variant naive --variant half_b "
                 "--precision float --summary --generate near_tangent:50\n" + other_cpu_output + "```\n")
    cpu_marker = "<!-- docs-run: depends on the CPU: half_b (self-test: as another CPU's kernel would answer) -->\n"
    # A benchmark block documented on the branch this machine did not take: a met target's line, run where it is
    # missed (and its reasons printed under it), and the other way round.
    met = "  audit / naive double, uniform                          40.00x  target <= 40x  met"
    missed = ("  audit / naive double, uniform                         135.40x  target <= 40x  MISSED\n"
              "      needs 95.4x of 135.4x gone (70%)\n      the lines cost 1601 ns per case-target\n")
    bench_block = ("{marker}```\n$ rayverify variants > /dev/null && printf 'targets, this run:\\n{printed}'\n"
                   "targets, this run:\n{documented}\n```\n")
    bench_marker = "<!-- docs-run: figures vary (self-test: run times) -->\n"
    cases.update({
        "a CPU-dependent row with other figures, marked": (cpu_block.format(marker=cpu_marker), 0),
        "a CPU-dependent row with other figures, unmarked": (cpu_block.format(marker=""), 1),
        "a met target documented, missed when run": (bench_block.format(
            marker=bench_marker, printed=missed.replace("%", "%%").replace("\n", "\\n"), documented=met), 0),
        "a missed target documented, met when run": (bench_block.format(
            marker=bench_marker, printed=met + "\\n", documented=missed.rstrip("\n")), 0),
        "a met target documented, missed when run, unmarked": (bench_block.format(
            marker="", printed=missed.replace("%", "%%").replace("\n", "\\n"), documented=met), 1),
        "an engine whose answers depend on the CPU, unmarked": (
            "<!-- docs-run: exit 1 -->\n```\n$ rayverify audit --engine self_test_cpu_engine --summary\n"
            "self_test_cpu_engine 1 self_test_cpu_engine 6.4%\n```\n", 1),
    })
    if probe.returncode != 1 or cpu_probe.returncode != 1 or not half_b_row:
        print(f"self-test: the probe audits exited {probe.returncode} and {cpu_probe.returncode}, expected 1 "
              "(with a half_b row)")
        return 1
    failed = 0
    with tempfile.TemporaryDirectory(prefix="rayverify-docs-run-self-test-") as repo:
        for name, (text, want) in cases.items():
            open(os.path.join(repo, "doc.md"), "w", encoding="utf-8").write(text)
            checker = Context(context.binary, repo)
            checker._cpu_dependent = {"self_test_cpu_engine"}  # as `rayverify engines` would list one
            checker._engines = {"self_test_cpu_engine"}
            got = run_all(checker, ["doc.md"], 1, False)
            verdict = "ok" if got == want else "WRONG"
            failed += got != want
            print(f"self-test: {name}: exit {got}, expected {want}: {verdict}")
    return 1 if failed else 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--binary", required=True, help="the rayverify executable to run")
    parser.add_argument("--repo", default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    parser.add_argument("--jobs", type=int, default=2, help="documents checked at once")
    parser.add_argument("--only", nargs="*", help="these documents (paths relative to the repository)")
    parser.add_argument("--regenerate", action="store_true", help="rewrite literal output blocks that differ")
    parser.add_argument("--self-test", action="store_true", help="check that the checker catches broken docs")
    parser.add_argument("--only-marked", nargs="+", default=(), metavar="MARKER",
                        help="only the blocks carrying one of these markers (e.g. \"figures vary\")")
    arguments = parser.parse_args()
    if not os.access(arguments.binary, os.X_OK):
        print(f"docs-run: error: {arguments.binary} is not an executable", file=sys.stderr)
        return 2
    unknown = [m for m in arguments.only_marked if not m.startswith(DIRECTIVES)]
    if unknown:
        print(f"docs-run: error: --only-marked {unknown}: not markers (docs/testing.md lists them)", file=sys.stderr)
        return 2
    context = Context(arguments.binary, arguments.repo, arguments.only_marked)
    if arguments.self_test:
        return self_test(context)
    return run_all(context, documents(context.repo, arguments.only), arguments.jobs, arguments.regenerate)


if __name__ == "__main__":
    sys.exit(main())
