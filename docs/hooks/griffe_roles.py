"""A Griffe extension for the API pages: Sphinx roles (``:class:`Name```) in the docstrings of the modules that the
submission builder inlines verbatim become markdown code spans on the page, and prose after a numpy section gets a ``Notes`` heading.

Those modules' sources are copied into every submitted file, so editing their docstrings would change the committed
submissions; every other module writes markdown (code spans, ``[name][dotted.path]`` cross-references) in its
docstrings, which tests/unit/test_docstrings.py checks.
"""

from __future__ import annotations

import re
from typing import Any

import griffe

VERBATIM = (
    'vtube_planning.onboard',
    'robotarium_exp.flight',
    'robotarium_exp.flight_data',
    'robotarium_exp.safety',
    'robotarium_exp.rps.utilities.barrier_rows',
)
"""The modules (and packages) whose docstrings stay as written: the builder inlines them verbatim."""

ROLE = re.compile(r':(?:py:)?[a-z]+:`~?\.?([^`]+)`')


def is_verbatim(module: str) -> bool:
    """Whether ``module`` is, or is inside, one of ``VERBATIM``."""
    return any(module == name or module.startswith(name + '.') for name in VERBATIM)


def markdown(text: str) -> str:
    """``text`` with each Sphinx role replaced by a code span of the name it shows (the last part after ``~``)."""

    def span(match: re.Match[str]) -> str:
        shown = match.group(1).split('.')[-1] if '~' in match.group(0) else match.group(1)
        return f'`{shown}`'

    return ROLE.sub(span, text)


def prose_after_sections(text: str) -> str:
    """``text`` with a paragraph of prose that follows a numpy section (``Parameters`` and its underline) put under a
    ``Notes`` heading: the numpy parser would read its words as parameter names."""
    blocks = text.split('\n\n')
    in_section = False
    for k, block in enumerate(blocks):
        lines = block.splitlines()
        if len(lines) >= 2 and set(lines[1].strip()) == {'-'}:
            in_section = True
        elif in_section and lines and len(lines[0].split()) > 4 and ' : ' not in lines[0]:
            blocks[k] = 'Notes\n-----\n' + block
            in_section = False
    return '\n\n'.join(blocks)


class SphinxRolesToMarkdown(griffe.Extension):
    """Rewrite the roles of the verbatim modules' docstrings once the object tree is loaded."""

    def on_object(self, *, obj: griffe.Object, loader: griffe.GriffeLoader, **kwargs: Any) -> None:
        if obj.docstring is not None and is_verbatim(obj.module.path):
            obj.docstring.value = prose_after_sections(markdown(obj.docstring.value))
