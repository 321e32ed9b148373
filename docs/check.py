#!/usr/bin/env python3
"""Checks the user documents: their links, and that their example commands run as written.

    python3 docs/check.py links
    python3 docs/check.py examples --bin target/release [FILE.md ...]

`links` reads README.md, BENCHMARKS.md, RELIABILITY.md, ARCHITECTURE.md and every page of the
guide (docs/src): every relative link and image must name a file that exists, and every
`#anchor` a heading of the page it points to (headings as GitHub and mdBook make them into
anchors). Files the guide includes whole ({{#include}}) are read from docs/src too, so they may
hold no relative links other than anchors.

`examples` runs every ```sh block of the given pages (by default README.md and every page of
the guide) as written, in a fresh scratch folder per page that holds a link to the repository's
examples/ (so `examples/data/...` works, and files made by an earlier block are there for a
later one), with the folder given by --bin first on the PATH (it must hold `edmd` and
`particles`). A block preceded by a line `<!-- no-run: REASON -->` is skipped: builds,
installs, long runs, windows. A ```text block preceded by `<!-- file: NAME -->` is written to
the scratch folder as NAME, so that the commands after it can read the file shown. Each block runs under `bash -e -o pipefail`; a block that fails
is printed with its output, and the script exits 1. Pages run side by side, one per processor
(--jobs N to choose).
"""

import argparse
import concurrent.futures
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SRC = os.path.join(ROOT, "docs", "src")
TOP = ["README.md", "BENCHMARKS.md", "RELIABILITY.md", "ARCHITECTURE.md"]

LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
INCLUDE = re.compile(r"\{\{#include\s+([^}\s]+)\s*\}\}")
FENCE = re.compile(r"^(\s*)(```+|~~~+)(.*)$")


def guide_pages():
    pages = []
    for d, _, files in os.walk(SRC):
        pages += [os.path.join(d, f) for f in sorted(files) if f.endswith(".md")]
    return sorted(pages)


def read(path):
    with open(path, encoding="utf-8") as f:
        return f.read()


def expand(path):
    """The page's text with its {{#include}}s in place, and the files it included."""
    text = read(path)
    included = []

    def sub(m):
        target = os.path.normpath(os.path.join(os.path.dirname(path), m.group(1)))
        included.append(target)
        return read(target)

    return INCLUDE.sub(sub, text), included


def outside_fences(text):
    """The lines outside fenced code blocks."""
    out, fence = [], None
    for line in text.splitlines():
        m = FENCE.match(line)
        if m and (fence is None or m.group(2).startswith(fence)):
            fence = m.group(2)[:3] if fence is None else None
            continue
        if fence is None:
            out.append(line)
    return out


def prose(text):
    """The text outside fenced code blocks and inline code spans."""
    return "\n".join(re.sub(r"`[^`]*`", "", line) for line in outside_fences(text))


def slug(heading):
    s = heading.strip().lower()
    s = re.sub(r"<[^>]+>", "", s)
    s = re.sub(r"[^\w\- ]", "", s)
    return s.replace(" ", "-")


def anchors(text):
    seen, out = {}, set()
    for line in outside_fences(text):
        m = re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
        if m:
            s = slug(m.group(1).replace("`", ""))
            n = seen.get(s, 0)
            seen[s] = n + 1
            out.add(s if n == 0 else f"{s}-{n}")
    return out


def check_links():
    problems = []
    pages = [os.path.join(ROOT, f) for f in TOP] + guide_pages()
    included_into_guide = set()
    for page in guide_pages():
        included_into_guide.update(expand(page)[1])
    texts = {}
    for page in pages:
        texts[page] = expand(page)[0] if page.startswith(SRC) else read(page)
    for page in pages:
        for target in LINK.findall(prose(texts[page])):
            if re.match(r"^[a-z]+:", target):
                continue
            path, _, frag = target.partition("#")
            if path and os.path.normpath(page) in included_into_guide:
                problems.append(f"{page}: {target}: a page the guide includes may link only to anchors")
                continue
            dest = os.path.normpath(os.path.join(os.path.dirname(page), path)) if path else page
            if not os.path.exists(dest):
                problems.append(f"{page}: {target}: no such file")
                continue
            if page.startswith(SRC) and not dest.startswith(SRC):
                problems.append(f"{page}: {target}: outside docs/src, which the book does not copy")
            if frag and dest.endswith(".md"):
                text = texts.get(dest) or (expand(dest)[0] if dest.startswith(SRC) else read(dest))
                if frag not in anchors(text):
                    problems.append(f"{page}: {target}: no heading makes the anchor #{frag}")
    for p in problems:
        print(p)
    print(f"links: {len(pages)} pages, {len(problems)} problems")
    return 1 if problems else 0


def blocks(path):
    """The page's ```sh blocks and named ```text blocks, in order, each as (line number, kind,
    text, and for `sh` the reason it is not run or None, for `file` the file's name)."""
    out, lines = [], read(path).splitlines()
    i = 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        start, fence, lang, body = i, m.group(2), m.group(3).strip(), []
        i += 1
        while i < len(lines) and not lines[i].strip().startswith(fence):
            body.append(lines[i])
            i += 1
        i += 1
        prev = next((lines[j].strip() for j in range(start - 1, -1, -1) if lines[j].strip()), "")
        text = "\n".join(body) + "\n"
        if lang in ("sh", "bash"):
            skip = re.match(r"<!--\s*no-run:?\s*(.*?)\s*-->", prev)
            out.append((start + 1, "sh", text, skip.group(1) if skip else None))
        elif lang == "text":
            named = re.match(r"<!--\s*file:\s*(\S+)\s*-->", prev)
            if named:
                out.append((start + 1, "file", text, named.group(1)))
    return out


def run_page(page, env):
    """Runs one page's blocks in its own scratch folder: (report lines, ran, failed, skipped)."""
    report, ran, failed, skipped = [], 0, 0, 0
    work = tempfile.mkdtemp(prefix="edmd-doc-")
    os.symlink(os.path.join(ROOT, "examples"), os.path.join(work, "examples"))
    try:
        for line, kind, body, extra in blocks(page):
            name = f"{os.path.relpath(page, ROOT)}:{line}"
            if kind == "file":
                with open(os.path.join(work, extra), "w", encoding="utf-8") as f:
                    f.write(body)
                continue
            if extra is not None:
                skipped += 1
                continue
            t0 = time.monotonic()
            r = subprocess.run(["bash", "-e", "-o", "pipefail", "-c", body], cwd=work,
                               env=env, stdin=subprocess.DEVNULL, capture_output=True,
                               text=True, timeout=600)
            ran += 1
            took = time.monotonic() - t0
            if r.returncode != 0:
                failed += 1
                report.append(f"FAILED {name} (exit {r.returncode}, {took:.1f} s):\n{body}\n"
                              f"--- stdout\n{r.stdout[-2000:]}\n--- stderr\n{r.stderr[-2000:]}")
            else:
                report.append(f"ok {name} ({took:.1f} s)")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return report, ran, failed, skipped


def check_examples(bin_dir, pages, jobs):
    bin_dir = os.path.abspath(bin_dir)
    for prog in ("edmd", "particles"):
        if not os.access(os.path.join(bin_dir, prog), os.X_OK):
            sys.exit(f"examples: no {prog} in {bin_dir}")
    env = dict(os.environ, PATH=bin_dir + os.pathsep + os.environ["PATH"])
    failed = ran = skipped = 0
    # Pages share nothing (each has its own scratch folder), so they run side by side; their
    # reports are printed in page order.
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        for report, r, f, s in pool.map(lambda page: run_page(page, env), pages):
            for entry in report:
                print(entry, flush=True)
            ran, failed, skipped = ran + r, failed + f, skipped + s
    print(f"examples: {ran} blocks ran, {failed} failed, {skipped} not run (marked no-run)")
    return 1 if failed else 0


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = p.add_subparsers(dest="what", required=True)
    sub.add_parser("links")
    ex = sub.add_parser("examples")
    ex.add_argument("--bin", required=True, help="folder holding edmd and particles")
    ex.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                    help="pages run at once (default: one per processor)")
    ex.add_argument("pages", nargs="*", help="pages (default: README.md and the guide)")
    a = p.parse_args()
    if a.what == "links":
        return check_links()
    pages = [os.path.abspath(x) for x in a.pages] or [os.path.join(ROOT, "README.md")] + guide_pages()
    if a.jobs < 1:
        p.error("--jobs must be at least 1")
    return check_examples(a.bin, pages, a.jobs)


if __name__ == "__main__":
    sys.exit(main())
