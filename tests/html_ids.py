"""The ids of an HTML page and the references to them, read with the standard library's parser
(no code from the project), for the tests that every id is unique and every reference resolves."""
from __future__ import annotations

import re
from collections import Counter
from html.parser import HTMLParser

_URL = re.compile(r"url\(\s*['\"]?#([^'\")\s]+)")


class _Ids(HTMLParser):
    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.ids: Counter = Counter()
        self.references: list[str] = []

    def handle_starttag(self, tag, attrs):
        for name, value in attrs:
            if value is None:
                continue
            if name == "id":
                self.ids[value] += 1
            elif name in ("href", "xlink:href") and value.startswith("#") and len(value) > 1:
                self.references.append(value[1:])
            self.references += _URL.findall(value)  # clip-path="url(#...)", style="...url(#...)"

    handle_startendtag = handle_starttag


def page_ids(html_text: str) -> tuple[list[str], list[str]]:
    """The ids that occur more than once in the page, and the references (``href="#X"``,
    ``xlink:href="#X"``, ``url(#X)``) to an id the page does not define."""
    parser = _Ids()
    parser.feed(html_text)
    parser.close()
    repeated = sorted(i for i, n in parser.ids.items() if n > 1)
    dangling = sorted({r for r in parser.references if r not in parser.ids})
    return repeated, dangling
