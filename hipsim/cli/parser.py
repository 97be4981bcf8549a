"""The command line's parser: one-line usage errors, no abbreviations, negative numbers as values, the option table applied.

:class:`HipsimParser` is the parser of ``hipsim`` and (through
``add_subparsers``) of every command. :func:`apply_table` holds every option
the commands add against :mod:`hipsim.cli.option_table`: each must be
declared there; a numeric one's values are checked against its hard range
(refused) and plausible range (warned of) as they are read, and its unit is
added to its ``--help``. :func:`rewrite_aliases` turns an old spelling
(``--model``) into the new one (``--engine``), with a warning.
"""

from __future__ import annotations

import argparse
import re
import sys

from ..exceptions import HipsimError
from .option_table import ALIASES, NEEDS, OPTIONS
from .options import Option, read_number

__all__ = [
    "HipsimParser",
    "UsageError",
    "apply_table",
    "command_parsers",
    "idle_option",
    "rewrite_aliases",
    "undeclared",
]

#: What argparse would take for an option but is a number: -1, -.5, -1,1 (--weights), -90:90:1 (--deltas).
_NEGATIVE_NUMBER = re.compile(r"^-\.?\d")


class UsageError(HipsimError):
    """A command line argparse cannot read (an unknown option, a missing value, a value out of range): one line."""


class HipsimParser(argparse.ArgumentParser):
    """``argparse`` with the rules of hipsim's command line.

    - abbreviations are off: ``--control 2`` is never read as ``--controller 2``;
    - a word that starts with ``-`` and a digit is a value (``--weights -1,1``);
    - a usage error is a :class:`UsageError` (main prints it as one line, exit status 2), not a usage block.
    """

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("allow_abbrev", False)
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = _NEGATIVE_NUMBER

    def error(self, message: str):
        command = self.prog.split(" ", 1)[1] if " " in self.prog else ""
        message = re.sub(r"^argument (--[\w-]+)(/[\w-]+)?: (\1 )", r"\3", message)  # the refusal names the option
        raise UsageError(f"{command}: {message}" if command else message)


def command_parsers(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    """Each command's parser, by name."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return dict(action.choices)
    return {}


def _checked_type(option: Option, base, notes: list[str]):
    """An argparse ``type``: the option's text checked against its ranges; warnings go to ``notes`` and standard error.

    What it returns is what the command asked for: its own ``type`` (``float``, ``int``, or a parser of its own)
    applied to the text, or the text itself when the command reads the text (a list, ``K:KIND``).
    """

    def convert(text: str):
        if not isinstance(text, str):  # a default given as a number: declared by the command, not typed
            return text
        values, warnings, refusal = read_number(option, text)
        if refusal:
            raise argparse.ArgumentTypeError(refusal)
        for warning in warnings:
            notes.append(warning)
            print(f"hipsim: warning: {warning}", file=sys.stderr)
        if base is None or base is str:
            return text
        if base is float or base is int:
            return base(values[0]) if option.kind != "numbers" else text
        return base(text)

    convert.__name__ = option.name  # argparse names the type in its own messages
    return convert


def _deprecated_type(option: Option, base, notes: list[str]):
    def convert(text):
        warning = f"{option.name} is deprecated: use {option.deprecated}"
        notes.append(warning)
        print(f"hipsim: warning: {warning}", file=sys.stderr)
        return text if base is None else base(text)

    return convert


def apply_table(parser: argparse.ArgumentParser) -> list[str]:
    """Hold every command's options against the table: checked types, units in ``--help``.

    Args:
        parser: the ``hipsim`` parser, its commands added.

    Returns:
        The list the checks append their warnings to while a command line is read (for a page's provenance).
        An option the table does not declare is left as its command added it (:func:`undeclared` lists them;
        a test holds the list empty), so that a command added in parallel still runs.
    """
    notes: list[str] = []
    for _command, sub in command_parsers(parser).items():
        for action in sub._actions:
            names = [name for name in action.option_strings if name.startswith("--") and name != "--help"]
            if not names:
                continue
            option = OPTIONS.get(names[0])
            if option is None:
                continue
            if option.numeric:
                action.type = _checked_type(option, action.type, notes)
            elif option.deprecated:
                action.type = _deprecated_type(option, action.type, notes)
            if action.help and action.help is not argparse.SUPPRESS:
                action.help += option.help_suffix().replace("%", "%%")
    return notes


def undeclared(parser: argparse.ArgumentParser) -> list[str]:
    """``hipsim COMMAND --option`` for each option a command adds that the table does not declare."""
    return [
        f"hipsim {command} {action.option_strings[0]}"
        for command, sub in command_parsers(parser).items()
        for action in sub._actions
        if action.option_strings
        and action.option_strings[0].startswith("--")
        and action.option_strings[0] != "--help"
        and action.option_strings[0] not in OPTIONS
    ]


def rewrite_aliases(words: list[str], notes: list[str] | None = None) -> list[str]:
    """A command line with each deprecated spelling of its command replaced by the new one, warning of each.

    Args:
        words: the command line after ``hipsim`` (the command first).
        notes: where the warnings are appended as well (for a page's provenance).
    """
    if not words or words[0].startswith("-"):
        return list(words)
    aliases = ALIASES.get(words[0], {})
    out = [words[0]]
    for word in words[1:]:
        name, sep, value = word.partition("=")
        if name in aliases:
            warning = f"{name} is deprecated in 'hipsim {words[0]}': use {aliases[name]}"
            print(f"hipsim: warning: {warning}", file=sys.stderr)
            if notes is not None:
                notes.append(warning)
            word = aliases[name] + sep + value
        out.append(word)
    return out


def idle_option(words: list[str]) -> str | None:
    """Why an option typed would do nothing without another (:data:`~hipsim.cli.option_table.NEEDS`), or None.

    Args:
        words: the command line after ``hipsim`` (the command first), aliases rewritten.
    """
    if not words or words[0].startswith("-"):
        return None
    typed = {word.split("=", 1)[0] for word in words[1:] if word.startswith("--")}
    for option, needed in NEEDS.get(words[0], {}).items():
        if option in typed and needed not in typed:
            return f"{words[0]}: {option} applies to {needed}: give {needed}, or drop {option}"
    return None
