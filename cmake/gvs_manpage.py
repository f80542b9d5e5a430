#!/usr/bin/python3
"""Writes a man(7) page for a CLI11 program from the help it prints: the
program's --help and --version, and every subcommand's --help, recursively
(`PROGRAM SUB --help`, `PROGRAM SUB SUBSUB --help`). Run at build time
(cmake/GvsPackage.cmake), so the page says what the program says.

usage: gvs_manpage.py PROGRAM OUT.1 [EMULATOR...]   (also writes OUT.1.gz, as Debian installs man pages)
EMULATOR: runs PROGRAM when it is built for another architecture (the arm64
cross build: qemu-aarch64 -L SYSROOT, its CMAKE_CROSSCOMPILING_EMULATOR).
"""
import gzip
import os
import re
import subprocess
import sys

ITEM = re.compile(r"^  (\S.*?)(?: {2,}(\S.*))?$")  # "  --name TYPE     description"


EMULATOR = []


def run(cmd):
    r = subprocess.run(EMULATOR + cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if r.returncode != 0:
        sys.exit("gvs_manpage.py: %s exited %d:\n%s" % (" ".join(cmd), r.returncode, r.stdout))
    return r.stdout


def esc(text):
    """Roff text: backslashes, and a leading dot or quote that roff would read as a request."""
    text = text.replace("\\", "\\e")
    return "\\&" + text if text[:1] in (".", "'") else text


def opt(text):
    """An option or command name: minus signs, not hyphens."""
    return esc(text).replace("-", "\\-")


def parse(help_text):
    """(description, usage, [(section, [(name, [description lines])])], footer lines) of CLI11's help."""
    lines = help_text.rstrip("\n").split("\n")
    description = lines[0]
    usage = lines[1][len("Usage: "):] if lines[1].startswith("Usage: ") else lines[1]
    sections, footer = [], []
    items = None
    for line in lines[2:]:
        if not line.strip():
            items = None  # a section ends at a blank line
            continue
        if not line.startswith(" ") and line.endswith(":") and " " not in line[:-1].strip():
            items = []
            sections.append((line[:-1], items))
        elif items is not None and ITEM.match(line):
            name, text = ITEM.match(line).groups()
            items.append((name, [text] if text else []))
        elif items is not None and items and line.startswith("    "):
            indent = len(line) - len(line.lstrip())
            items[-1][1].append(" " * max(0, indent - 30) + line.strip())
        else:
            items = None
            footer.append(line)
    return description, usage, sections, footer


def entries(out, items):
    for name, text in items:
        out.append(".TP")
        out.append("\\fB%s\\fR" % opt(name))
        for i, line in enumerate(text):
            if i > 0:
                out.append(".br")
            out.append(esc(line))


def main(program, out_path):
    name = os.path.basename(program)
    version = run([program, "--version"]).strip().split("\n")[0]
    description, usage, sections, footer = parse(run([program, "--help"]))
    summary = description.split(": ", 1)[1] if description.startswith(name + ": ") else description
    out = ['.\\" Generated from `%s --help` and its commands\' --help by cmake/gvs_manpage.py; do not edit.' % name,
           '.TH %s 1 "" "%s" "User Commands"' % (name.upper(), esc(version)),
           ".SH NAME", "%s \\- %s" % (name, esc(summary.split(". ")[0].rstrip("."))),
           ".SH SYNOPSIS", ".B %s" % name, opt(usage.split(" ", 1)[1] if " " in usage else ""),
           ".SH DESCRIPTION", esc(summary)]
    commands = []
    for title, items in sections:
        if title == "Subcommands":
            commands = [n for n, _ in items]
            out.append(".SH COMMANDS")
            for n, text in items:
                out += [".TP", "\\fB%s %s\\fR" % (name, opt(n))] + [esc(t) for t in text]
        else:
            out.append(".SH %s" % esc(title.upper()))
            entries(out, items)

    def command(path):
        desc, use, secs, foot = parse(run([program] + path + ["--help"]))
        out.extend([".SS \"%s\"" % opt(" ".join([name] + path)), esc(desc), ".PP", "Usage: \\fB%s\\fR" % opt(use)])
        subs = []
        for title, items in secs:
            out.append(".PP")
            out.append("\\fI%s:\\fR" % esc(title))
            entries(out, items)
            if title == "Subcommands":
                subs = [n for n, _ in items]
        for line in foot:
            out.extend([".PP", esc(line.strip())])
        for s in subs:
            command(path + [s])

    if commands:
        out.append(".SH \"COMMAND OPTIONS\"")
        for c in commands:
            command([c])
    for line in footer:
        head, _, rest = line.partition(": ")
        if rest and head[:1].isupper() and len(head.split()) <= 2:
            title = "SEE ALSO" if head == "Documentation" else head.upper()
            out.extend([".SH %s" % esc(title), esc(rest)])
        else:
            out.extend([".PP", esc(line)])
    text = ("\n".join(out) + "\n").encode()
    with open(out_path, "wb") as f:
        f.write(text)
    with open(out_path + ".gz", "wb") as raw:  # no name or time in the header: the same bytes every build
        with gzip.GzipFile(filename="", mode="wb", fileobj=raw, compresslevel=9, mtime=0) as f:
            f.write(text)


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    EMULATOR = sys.argv[3:]
    main(sys.argv[1], sys.argv[2])
