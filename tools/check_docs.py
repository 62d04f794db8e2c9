#!/usr/bin/python3
"""Checks that the outputs pasted in the README and docs/ are what the binaries print today.

A pasted output is a fenced block preceded by a marker comment, invisible when rendered:

    <!-- check -->                     the block's "$ " lines are commands, run in order; the
                                       lines after each are what it prints (stdout)
    <!-- check excerpt -->             the same, but the block's lines need only appear in that
                                       order among the printed lines (stdout, then stderr)
    <!-- check run: COMMAND -->        the block is COMMAND's output (no "$ " lines in it)
    <!-- check file=PATH -->           the block is the content of PATH, written by an earlier block
    <!-- check status=2 -->            the commands must exit with 2; their stderr is compared
                                       (a command with no lines after it is a step that must
                                       succeed, such as mkdir)

Options combine (`<!-- check excerpt run: build/bin/analyze -->`). In an expected block, a line
that starts with "..." (after spaces) stands for any number of printed lines, and a line that
ends with " ..." matches a printed line that starts with what comes before it.

Commands are split like a shell would split them (shlex) but run with an argument vector, never a
shell. Each document's commands run in a fresh folder laid out like a clone (build/ is the
--build_dir, tools/, tests/ and data/ link to the source tree, ../shared to --shared), in the order
of its blocks, so that a block may use a file an earlier block of the same document wrote. Before comparing, both
sides lose trailing blanks, the run's folder reads as ~/accelcal, and the text that changes from run
to run (elapsed times, the build's commit) is masked; see MASKS.

Usage: check_docs.py --build_dir=BUILD --source_dir=SRC --shared=SHARED FILE.md...
Exit status: 0 when every block matches, 1 when one does not (a diff for each is printed),
2 on bad usage, 77 when the shared data are missing (ctest's skip).
"""

import argparse
import difflib
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile

# Text that changes from run to run, replaced on both sides before comparing.
MASKS = [
    # the commit in --version lines and report footers
    (re.compile(r"commit [0-9a-f]{7,40}(-modified)?"), "commit C"),
    # a calibration file's checksum: the file records when and by which build it was written
    (re.compile(r"(calibration: \S+\.json \(sha256 )[0-9a-f]{64}"), r"\1S"),
    # elapsed times: "in 1.4 s", "2.6 s on 2 threads", "0.9 s to start", "about 38 s left"
    (re.compile(r"\b\d+(\.\d+)? s (on \d+|elapsed|to start|for the tasks|inside them|left)\b"),
     r"T s \2"),
    (re.compile(r"\bin \d+(\.\d+)? s\b"), "in T s"),
    (re.compile(r"\b(\d+) threads?, \d+(\.\d+)? s\)"), r"\1 threads, T s)"),
    (re.compile(r"\b\d+(\.\d+)? ms\b"), "T ms"),
]

MARKER = re.compile(r"^<!--\s*check\b(.*?)-->\s*$")


class Block:
    def __init__(self, path, line, options, text):
        self.path, self.line, self.text = path, line, text
        self.excerpt = False
        self.status = 0
        self.file = None
        self.run = None
        opts = options.strip()
        if "run:" in opts:
            opts, run = opts.split("run:", 1)
            self.run = run.strip()
        for word in opts.split():
            if word == "excerpt":
                self.excerpt = True
            elif word.startswith("status="):
                self.status = int(word[len("status="):])
            elif word.startswith("file="):
                self.file = word[len("file="):]
            else:
                raise ValueError(f"{path}:{line}: unknown check option '{word}'")


def read_blocks(path):
    lines = open(path, encoding="utf-8").read().split("\n")
    blocks, i = [], 0
    while i < len(lines):
        m = MARKER.match(lines[i])
        if not m:
            i += 1
            continue
        if i + 1 >= len(lines) or not lines[i + 1].startswith("```"):
            raise ValueError(f"{path}:{i + 1}: a check marker must be followed by a fenced block")
        j = i + 2
        while j < len(lines) and not lines[j].startswith("```"):
            j += 1
        if j >= len(lines):
            raise ValueError(f"{path}:{i + 2}: the fenced block is not closed")
        blocks.append(Block(path, i + 1, m.group(1), lines[i + 2:j]))
        i = j + 1
    return blocks


def split_commands(block):
    """(command, expected lines) pairs; a command may continue over lines until its quotes close."""
    if block.run is not None:
        return [(block.run, block.text)]
    pairs, i, lines = [], 0, block.text
    if block.file is not None and not any(l.startswith("$ ") for l in lines):
        return [(None, lines)]
    while i < len(lines):
        if not lines[i].startswith("$ "):
            raise ValueError(f"{block.path}:{block.line}: expected a '$ ' command line, got '{lines[i]}'")
        command = lines[i][2:]
        i += 1
        while command.endswith("\\") and i < len(lines):  # a shell's line continuation
            command = command[:-1].rstrip() + " " + lines[i].strip()
            i += 1
        while True:
            try:
                shlex.split(command)
                break
            except ValueError:  # an open quote: the command goes on
                if i >= len(lines):
                    raise ValueError(f"{block.path}:{block.line}: unclosed quote in a command")
                command += "\n" + lines[i]
                i += 1
        expected = []
        while i < len(lines) and not lines[i].startswith("$ "):
            expected.append(lines[i])
            i += 1
        pairs.append((command, expected))
    return pairs


def normalise(lines, workdir):
    out = []
    for line in lines:
        line = line.replace(workdir, "~/accelcal").rstrip()
        for pattern, repl in MASKS:
            line = pattern.sub(repl, line)
        out.append(line)
    while out and not out[-1]:
        out.pop()
    return out


def is_gap(line):
    return line.strip().startswith("...")


def line_matches(expected, actual):
    if expected.endswith(" ...") and not is_gap(expected):
        return actual.startswith(expected[:-4].rstrip())
    return expected == actual


def matches(expected, actual, excerpt):
    """Whether expected (with gaps) matches actual: all of it, or in order as an excerpt."""
    lines = [l for l in expected if not (excerpt and not l.strip())]
    pos, gap = 0, excerpt
    for k, want in enumerate(lines):
        if is_gap(want):
            gap = True
            continue
        if gap:
            while pos < len(actual) and not line_matches(want, actual[pos]):
                pos += 1
            if pos == len(actual):
                return False
        elif pos >= len(actual) or not line_matches(want, actual[pos]):
            return False
        pos += 1
        gap = excerpt
    return gap or pos == len(actual)


def make_workdir(args):
    """A fresh folder laid out like a clone: build/, tools/, tests/, data/, docs/figures/, ../shared."""
    root = tempfile.mkdtemp(prefix="accelcal-docs-")
    workdir = os.path.join(root, "accelcal")
    os.mkdir(workdir)
    os.symlink(os.path.abspath(args.shared), os.path.join(root, "shared"))
    os.symlink(os.path.abspath(args.build_dir), os.path.join(workdir, "build"))
    for name in ("tools", "tests", "data"):
        os.symlink(os.path.join(os.path.abspath(args.source_dir), name), os.path.join(workdir, name))
    os.makedirs(os.path.join(workdir, "docs", "figures"))
    return workdir


def check(documents, args, quiet=False):
    """Runs every block of the documents; returns (outputs checked, failures, folders used)."""
    failures, count = 0, 0
    updates = {}  # path -> (marker line, pasted lines, printed lines), with --update
    env = dict(os.environ)
    env["PYTHONPATH"] = os.path.join(os.path.abspath(args.build_dir), "python")
    workdirs = []
    for path, blocks in documents:
        workdir = make_workdir(args)  # each document starts from a clean folder
        workdirs.append(workdir)
        for block in blocks:
            for command, expected in split_commands(block):
                count += 1
                where = f"{path}:{block.line}"
                if command is not None:
                    try:
                        run = subprocess.run(shlex.split(command), cwd=workdir, env=env,
                                             stdin=subprocess.DEVNULL, capture_output=True,
                                             text=True, timeout=args.timeout)
                    except (OSError, subprocess.TimeoutExpired) as e:
                        print(f"FAIL {where}: {command.splitlines()[0]}: {e}")
                        failures += 1
                        continue
                    # a command with nothing pasted after it is a step (mkdir, a generator): it must succeed
                    status = block.status if expected else 0
                    if run.returncode != status:
                        print(f"FAIL {where}: {command.splitlines()[0]}: exit status "
                              f"{run.returncode}, expected {status}\n{run.stderr[-2000:]}")
                        failures += 1
                        continue
                    if not expected:
                        print(f"ok   {where}: {command.splitlines()[0][:100]} (a step)")
                        continue
                    if status != 0:
                        actual = run.stderr
                    elif block.excerpt:
                        actual = run.stdout + run.stderr
                    else:
                        actual = run.stdout
                if block.file is not None:
                    try:
                        actual = open(os.path.join(workdir, block.file), encoding="utf-8").read()
                    except OSError as e:
                        print(f"FAIL {where}: {e}")
                        failures += 1
                        continue
                want = normalise(expected, workdir)
                got = normalise(actual.split("\n"), workdir)
                if matches(want, got, block.excerpt):
                    print(f"ok   {where}: {(command or block.file).splitlines()[0][:100]}")
                else:
                    failures += 1
                    print(f"FAIL {where}: {(command or block.file).splitlines()[0]}")
                    sys.stdout.writelines(difflib.unified_diff(
                        [l + "\n" for l in want], [l + "\n" for l in got],
                        "pasted", "printed now", n=2))
                    # A whole block of one command's output, without gaps, can be pasted again.
                    if (args.update and not block.excerpt and command is not None and
                            len(split_commands(block)) == 1 and not any(map(is_gap, expected))):
                        printed = [l.replace(workdir, "~/accelcal").rstrip()
                                   for l in actual.rstrip("\n").split("\n")]
                        updates.setdefault(path, []).append((block.line, expected, printed))
    for path, changes in updates.items():  # --update: paste the printed output into the files
        lines = open(path, encoding="utf-8").read().split("\n")
        for line, expected, printed in sorted(changes, reverse=True):
            start = line + 1  # the block's first line (0-based: the marker is line - 1)
            offset = 1 if lines[start].startswith("$ ") else 0
            lines[start + offset:start + offset + len(expected)] = printed
        open(path, "w", encoding="utf-8").write("\n".join(lines))
        print(f"check_docs: pasted {len(changes)} block(s) again in {path}")
    return count, failures, workdirs


def self_test(args):
    """The checker against documents whose answer is known: one true, three false."""
    args.update = False
    course = "../shared/data/tp2-2018"
    first = make_workdir(args)
    printed = subprocess.run(["build/bin/linear_ls", f"--data_dir={course}"], cwd=first,
                             capture_output=True, text=True, check=True).stdout
    used = [first]
    lines = printed.rstrip("\n").split("\n")
    changed = [re.sub(r"(scale_x +[-+]\d\.\d{3})(\d)", lambda m: m.group(1) + str((int(m.group(2)) + 1) % 10), l)
               for l in lines]
    assert changed != lines, "no scale_x line in linear_ls's output"
    run = f"<!-- check run: build/bin/linear_ls --data_dir={course} -->"
    cases = [  # (name, document, whether it must pass)
        ("the truth", [run, "```"] + lines + ["```"], True),
        ("a changed digit", [run, "```"] + changed + ["```"], False),
        ("a line never printed", [run.replace("check run:", "check excerpt run:"), "```",
                                  lines[0], "  bias_x is exactly zero", "```"], False),
        ("a wrong exit status", ["<!-- check status=2 -->", "```",
                                 f"$ build/bin/linear_ls --data_dir={course}", lines[0], "```"], False),
    ]
    folder = tempfile.mkdtemp(prefix="accelcal-docs-self-test-")
    wrong = 0
    for name, document, should_pass in cases:
        path = os.path.join(folder, name.replace(" ", "_") + ".md")
        with open(path, "w", encoding="utf-8") as f:
            f.write("\n".join(document) + "\n")
        _, failures, workdirs = check([(path, read_blocks(path))], args)
        used += workdirs
        if (failures == 0) != should_pass:
            wrong += 1
            print(f"SELF-TEST WRONG: {name}: the checker said {'fail' if failures else 'pass'}")
    print(f"check_docs --self_test: {len(cases) - wrong} of {len(cases)} known answers given")
    for workdir in [os.path.join(folder, "x")] + used:
        shutil.rmtree(os.path.dirname(workdir), ignore_errors=True)
    return 1 if wrong else 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--build_dir", required=True)
    parser.add_argument("--source_dir", required=True)
    parser.add_argument("--shared", required=True)
    parser.add_argument("--timeout", type=float, default=600, help="seconds per command")
    parser.add_argument("--self_test", action="store_true",
                        help="check that the checker fails on a changed digit, a missing line and a "
                             "wrong exit status, and passes on the truth")
    parser.add_argument("--update", action="store_true",
                        help="paste the printed output again into whole blocks (one command, no "
                             "gaps) that differ; excerpts are left to be edited by hand")
    parser.add_argument("files", nargs="*")
    args = parser.parse_args()
    if not os.path.isdir(os.path.join(args.shared, "data")):
        print(f"check_docs: {args.shared}/data not found: the shared data are needed; skipped")
        return 77
    if args.self_test:
        return self_test(args)
    if not args.files:
        print("check_docs: no FILE.md given; see --help", file=sys.stderr)
        return 2
    try:
        documents = [(f, read_blocks(f)) for f in args.files]
        for _, blocks in documents:
            for block in blocks:
                split_commands(block)
    except (OSError, ValueError) as e:
        print(f"check_docs: {e}", file=sys.stderr)
        return 2

    count, failures, workdirs = check(documents, args)
    if failures:  # the folders stay, to look at what was printed
        where = f"run in {', '.join(workdirs)}"
    else:
        for workdir in workdirs:
            shutil.rmtree(os.path.dirname(workdir), ignore_errors=True)
        where = "their folders removed"
    print(f"check_docs: {count - failures} of {count} pasted outputs match"
          f" ({len(documents)} files; {where})")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
