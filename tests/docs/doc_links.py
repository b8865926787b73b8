"""doc_links.py SOURCE_DIR: every relative link of README.md and docs/*.md — [text](path) and
[text](path#anchor) — names a file of the repository, and its anchor a heading of that file
(GitHub's anchors: the heading lower-cased, punctuation dropped, spaces as hyphens, a repeated
heading numbered -1, -2, …). Links to the web (http:, https:, mailto:) are not followed."""
import os
import re
import sys

LINK = re.compile(r"(?<!!)\[[^\]]*\]\(([^)\s]+)\)")
HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")


def anchors(path):
    """The anchors of a Markdown file's headings (outside fenced code)."""
    seen, out, fenced = {}, set(), False
    for line in open(path, encoding="utf-8"):
        if line.startswith("```"):
            fenced = not fenced
            continue
        m = None if fenced else HEADING.match(line.rstrip("\n"))
        if not m:
            continue
        text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", m.group(2))  # a link's text
        slug = re.sub(r"[^\w\- ]", "", text.strip().lower().replace("`", "")).replace(" ", "-")
        n = seen.get(slug, 0)
        seen[slug] = n + 1
        out.add(slug if n == 0 else f"{slug}-{n}")
    return out


def main(source):
    docs = ["README.md"] + [os.path.join("docs", f) for f in sorted(os.listdir(os.path.join(source, "docs")))
                            if f.endswith(".md")]
    broken, checked = [], 0
    for doc in docs:
        lines = open(os.path.join(source, doc), encoding="utf-8").read().split("\n")
        fenced = False
        for number, line in enumerate(lines, 1):
            if line.startswith("```"):
                fenced = not fenced
            if fenced or line.startswith("    "):
                continue
            for target in LINK.findall(re.sub(r"`[^`]*`", "", line)):
                if re.match(r"^[a-z]+:", target):
                    continue
                checked += 1
                path, _, anchor = target.partition("#")
                file = os.path.normpath(os.path.join(os.path.dirname(os.path.join(source, doc)), path)) if path \
                    else os.path.join(source, doc)
                if not os.path.exists(file):
                    broken.append(f"{doc}:{number}: {target}: no file {os.path.relpath(file, source)}")
                elif anchor and file.endswith(".md") and anchor not in anchors(file):
                    broken.append(f"{doc}:{number}: {target}: no heading #{anchor} in {os.path.relpath(file, source)}")
    for b in broken:
        print("FAIL " + b)
    print(f"doc_links: {checked} links checked, {len(broken)} broken")
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
