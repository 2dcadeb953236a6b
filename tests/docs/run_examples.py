#!/usr/bin/env python3
"""Runs every code block of README.md and docs/*.md (the convention: docs/testing.md).

    run_examples.py --source DIR --build DIR [--list] [FILE...]

Blocks tagged sh, bash, shell or console run in bash, python blocks in Python with the built module
on PYTHONPATH, cpp blocks compiled against the built library and run. Each page runs in its own
scratch directory that mirrors the source tree (scenes/, examples/, build/ ... as links), in order,
so a block may read what an earlier block of its page wrote. The first block that fails stops the
run with its file and line.
"""
import argparse
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import time

RUNNABLE = {"sh": "sh", "bash": "sh", "shell": "sh", "console": "console", "python": "python", "cpp": "cpp"}
DIRECTIVE = re.compile(r"^\s*<!--\s*doc-test:\s*(.*?)\s*-->\s*$")
FENCE = re.compile(r"^(\s*)(```+|~~~+)\s*([\w+-]*)")
REPLACE = re.compile(r'^replace\s+"((?:[^"\\]|\\.)*)"\s*=>\s*"((?:[^"\\]|\\.)*)"$')
BLOCK_TIMEOUT_S = 300


class DocError(Exception):
    pass


class Block:
    def __init__(self, path, line, lang, text, directives):
        self.path, self.line, self.lang, self.text = path, line, lang, text
        self.skip = None
        self.env = {}
        self.file = None
        for where, d in directives:
            if d.startswith("skip"):
                reason = d[4:].strip()
                if not (reason.startswith("(") and reason.endswith(")") and len(reason) > 2):
                    raise DocError(f"{where}: skip needs a reason in parentheses: skip (needs a GPU)")
                self.skip = reason[1:-1]
            elif d.startswith("replace"):
                m = REPLACE.match(d)
                if not m:
                    raise DocError(f'{where}: expected replace "OLD" => "NEW", got: {d}')
                old, new = (s.replace('\\"', '"') for s in m.groups())
                if old not in self.text:
                    raise DocError(f"{where}: replace: '{old}' is not in the block below (stale substitution)")
                self.text = self.text.replace(old, new)
            elif d.startswith("file"):
                name = d[4:].strip()
                if not name or os.path.isabs(name) or ".." in name.split("/"):
                    raise DocError(f"{where}: file needs a relative path: file scenes/mine.json")
                self.file = name
            elif d.startswith("env"):
                for item in shlex.split(d[3:]):
                    name, sep, value = item.partition("=")
                    if not sep or not name:
                        raise DocError(f"{where}: env expects NAME=VALUE pairs, got '{item}'")
                    self.env[name] = value
            else:
                raise DocError(f"{where}: unknown doc-test directive '{d}' (skip, replace, env, file)")

    def where(self):
        return f"{self.path}:{self.line}"


def blocks_of(path, rel):
    """The fenced blocks of one markdown file, with the directives of the comments before each."""
    lines = open(path, encoding="utf-8").read().split("\n")
    out, pending, i = [], [], 0
    while i < len(lines):
        d = DIRECTIVE.match(lines[i])
        if d:
            pending.append((f"{rel}:{i + 1}", d.group(1)))
            i += 1
            continue
        f = FENCE.match(lines[i])
        if not f:
            if pending and lines[i].strip():
                raise DocError(f"{pending[0][0]}: a doc-test directive must stand right before a code block")
            i += 1
            continue
        indent, fence, lang = f.groups()
        start = i + 1
        body = []
        i += 1
        while i < len(lines) and not lines[i].strip().startswith(fence):
            body.append(lines[i][len(indent):] if lines[i].startswith(indent) else lines[i])
            i += 1
        i += 1
        kind = RUNNABLE.get(lang.lower())
        if any(d.startswith("file") for _, d in pending):
            out.append(Block(rel, start, "file", "\n".join(body) + "\n", pending))
        elif kind is None:
            if pending:
                raise DocError(f"{pending[0][0]}: directive before a '{lang or 'untagged'}' block, which never runs")
        else:
            out.append(Block(rel, start, kind, "\n".join(body) + "\n", pending))
        pending = []
    if pending:
        raise DocError(f"{pending[0][0]}: a doc-test directive at the end of the file")
    return out


LINK = re.compile(r"\]\(([^)\s]+)\)")


def slug(heading):
    """The anchor GitHub gives a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower().replace("`", ""))
    return text.replace(" ", "-")


def anchors(path):
    out, fenced = set(), False
    for line in open(path, encoding="utf-8"):
        if FENCE.match(line):
            fenced = not fenced
        elif not fenced and line.startswith("#"):
            out.add(slug(line.lstrip("#")))
    return out


def check_links(source, rel):
    """Every relative link of a page names a file that exists, and a heading of it after '#'."""
    here = os.path.dirname(os.path.join(source, rel))
    text = re.sub(r"(?ms)^\s*```.*?^\s*```", "", open(os.path.join(source, rel), encoding="utf-8").read())
    for target in LINK.findall(text):
        if re.match(r"^[a-z]+:", target):
            continue
        path, _, anchor = target.partition("#")
        full = os.path.normpath(os.path.join(here, path)) if path else os.path.join(source, rel)
        if not os.path.exists(full):
            raise DocError(f"{rel}: a link to {target}: no such file")
        if anchor and full.endswith(".md") and anchor not in anchors(full):
            raise DocError(f"{rel}: a link to {target}: no such heading")


def check_cli(source, build):
    """docs/cli.md's synopsis names every option of each `clsph COMMAND --help`, and no other; its
    tables describe every option of `clsph run`."""
    page = open(os.path.join(source, "docs", "cli.md"), encoding="utf-8").read()
    synopsis = page.split("```\n", 2)[1]
    by_command, command = {}, None
    for line in synopsis.split("\n"):
        m = re.match(r"^clsph (\w+)", line)
        if m:
            command = m.group(1)
        if command:
            by_command.setdefault(command, set()).update(re.findall(r"--[a-z][a-z-]*", line))
    table = set(re.findall(r"(?m)^\| `(--[a-z][a-z-]*)", page))
    tool = os.path.join(build, "host", "app", "clsph")
    for command in ("devices", "run", "resume", "surface", "render"):
        helptext = subprocess.run([tool, command, "--help"], stdout=subprocess.PIPE, text=True).stdout
        options = set(re.findall(r"(?m)^\s+(--[a-z][a-z-]*)", helptext)) - {"--help"}
        documented = by_command.get(command, set())
        if options != documented:
            raise DocError(f"docs/cli.md: the synopsis of clsph {command} differs from its --help: "
                           f"missing {sorted(options - documented)}, not an option {sorted(documented - options)}")
        if command == "run" and options != table:
            raise DocError(f"docs/cli.md: the option tables differ from clsph run --help: "
                           f"missing {sorted(options - table)}, not an option {sorted(table - options)}")


def check_lists(source):
    """docs/library.md's table lists every public header and no other; docs/layout.md names every
    top-level folder of the tree and every part of host/src."""
    page = open(os.path.join(source, "docs", "library.md"), encoding="utf-8").read()
    listed = set(re.findall(r"(?m)^\| `([a-z_]+\.hpp)`", page))
    headers = set(f for f in os.listdir(os.path.join(source, "host", "include", "clsph")) if f.endswith(".hpp"))
    if listed != headers:
        raise DocError(f"docs/library.md: the header table differs from host/include/clsph/: "
                       f"missing {sorted(headers - listed)}, not a header {sorted(listed - headers)}")
    layout = open(os.path.join(source, "docs", "layout.md"), encoding="utf-8").read()
    names = set(re.findall(r"(?m)^\s*([\w./-]+/)", layout))
    tree = set(d + "/" for d in os.listdir(source) if os.path.isdir(os.path.join(source, d))
               and not d.startswith(".") and d not in ("build", "out") and not d.startswith("build-"))
    tree |= set(d + "/" for d in os.listdir(os.path.join(source, "host", "src"))
                if os.path.isdir(os.path.join(source, "host", "src", d)))
    missing = sorted(d for d in tree if not any(n == d or n.startswith(d) for n in names))
    if missing:
        raise DocError(f"docs/layout.md: no line for {missing}")


def scratch_dir(source, build):
    """A directory that looks like the source tree (every top-level entry a link) with build/."""
    d = tempfile.mkdtemp(prefix="clsph-doc-")
    for name in os.listdir(source):
        if name in ("build", "out", ".git"):
            continue
        os.symlink(os.path.join(source, name), os.path.join(d, name))
    os.symlink(build, os.path.join(d, "build"))
    return d


def console_script(text):
    cmds = [l[2:] for l in text.split("\n") if l.startswith("$ ")]
    if not cmds:
        raise DocError("a console block with no '$ ' command line")
    return "\n".join(cmds) + "\n"


def cpp_program(text):
    if re.search(r"\bint\s+main\s*\(", text):
        return text
    head = [l for l in text.split("\n") if l.startswith("#include")]
    body = [l for l in text.split("\n") if not l.startswith("#include")]
    return "\n".join(head) + "\n\nint main() {\n" + "\n".join("    " + l for l in body) + "\n    return 0;\n}\n"


def run(block, cwd, env, args):
    env = dict(env, **block.env)
    if block.lang == "file":
        path = os.path.join(cwd, block.file)
        if os.path.islink(path) or os.path.islink(os.path.dirname(path)):
            raise DocError(f"file {block.file}: would write into the source tree (a linked folder)")
        os.makedirs(os.path.dirname(path) or cwd, exist_ok=True)
        open(path, "w").write(block.text)
        return 0, ""
    if block.lang in ("sh", "console"):
        script = block.text if block.lang == "sh" else console_script(block.text)
        cmd = ["bash", "-euo", "pipefail", "-c", script]
    elif block.lang == "python":
        cmd = [args.python, "-c", block.text]
    else:
        src = os.path.join(cwd, f"doc_block_{block.line}.cpp")
        exe = src[:-4]
        open(src, "w").write(cpp_program(block.text))
        link = open(os.path.join(args.build, "tests", "docs", "link_flags.txt")).read().split("\n")
        compiler, flags = link[0], [f for f in link[1:] if f]
        build = subprocess.run([compiler, "-std=c++17", "-O1", src, "-o", exe] + flags, cwd=cwd,
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if build.returncode != 0:
            return build.returncode, "compiling:\n" + build.stdout
        cmd = [exe]
    try:
        p = subprocess.run(cmd, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                           timeout=BLOCK_TIMEOUT_S, stdin=subprocess.DEVNULL)
    except subprocess.TimeoutExpired as e:
        out = e.stdout.decode(errors="replace") if isinstance(e.stdout, bytes) else (e.stdout or "")
        return 124, out + f"\n(timed out after {BLOCK_TIMEOUT_S} s)"
    return p.returncode, p.stdout


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--source", default=os.path.join(os.path.dirname(__file__), "..", ".."))
    ap.add_argument("--build", required=True)
    ap.add_argument("--python", default="/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable,
                    help="the Python the module was built for (default: Debian's, as CMake picks it)")
    ap.add_argument("--verbose", action="store_true", help="print every block's output")
    ap.add_argument("--list", action="store_true", help="list the blocks and what would run, run nothing")
    ap.add_argument("files", nargs="*", help="markdown files relative to the source (default: README.md docs/*.md)")
    args = ap.parse_args()
    source, args.build = os.path.realpath(args.source), os.path.realpath(args.build)
    files = args.files or ["README.md"] + sorted(
        os.path.join("docs", f) for f in os.listdir(os.path.join(source, "docs")) if f.endswith(".md"))
    try:
        pages = [(rel, blocks_of(os.path.join(source, rel), rel)) for rel in files]
        for rel in files + ([] if args.files else ["BENCHMARKS.md", "BENCHMARKS_HISTORY.md"]):
            check_links(source, rel)
        if not args.files:
            check_lists(source)
        if "docs/cli.md" in files and not args.list:
            check_cli(source, args.build)
    except DocError as e:
        print(f"doc-test: {e}", file=sys.stderr)
        return 1
    env = dict(os.environ)
    env["PATH"] = os.pathsep.join([os.path.join(args.build, "host", "app"), os.path.join(args.build, "bench"),
                                   env.get("PATH", "")])
    env["PYTHONPATH"] = os.pathsep.join(p for p in [os.path.join(args.build, "python"), env.get("PYTHONPATH")] if p)
    ran = skipped = 0
    for rel, blocks in pages:
        if args.list:
            for b in blocks:
                print(f"{b.where()}: {b.lang}: " + (f"skip ({b.skip})" if b.skip else "run"))
            continue
        cwd = None
        try:
            for b in blocks:
                if b.skip:
                    print(f"{b.where()}: {b.lang}: skipped ({b.skip})")
                    skipped += 1
                    continue
                cwd = cwd or scratch_dir(source, args.build)
                t = time.monotonic()
                try:
                    rc, out = run(b, cwd, env, args)
                except DocError as e:
                    rc, out = 1, str(e)
                if rc != 0:
                    print(out[-6000:])
                    print(f"{b.where()}: {b.lang} block failed (exit status {rc})", file=sys.stderr)
                    print(f"doc-test: {ran} passed, 1 failed, {skipped} skipped")
                    return 1
                ran += 1
                if args.verbose:
                    print(out)
                print(f"{b.where()}: {b.lang}: ok ({time.monotonic() - t:.1f} s)")
        finally:
            if cwd:
                shutil.rmtree(cwd, ignore_errors=True)
    if not args.list:
        print(f"doc-test: {ran} passed, 0 failed, {skipped} skipped")
    return 0


if __name__ == "__main__":
    sys.exit(main())
