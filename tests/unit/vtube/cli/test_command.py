"""What a command is: its record, the view of a result, the exit codes and the two ways to stop short."""

from __future__ import annotations

import dataclasses

import pytest

from vtube.cli.command import (
    EXIT_BAD_INPUT,
    EXIT_FAILED,
    EXIT_INTERRUPTED,
    EXIT_OK,
    BadInput,
    Command,
    Interrupted,
    View,
)


def test_the_exit_codes_are_the_documented_ones() -> None:
    assert (EXIT_OK, EXIT_FAILED, EXIT_BAD_INPUT, EXIT_INTERRUPTED) == (0, 1, 2, 130)


def test_a_view_defaults_to_text_only_and_success_and_is_frozen() -> None:
    view = View(('a',))
    assert (view.data, view.exit_code, view.error) == (None, EXIT_OK, None)
    with pytest.raises(dataclasses.FrozenInstanceError):
        view.exit_code = 1  # type: ignore[misc]


def test_a_command_holds_its_words_options_call_and_view() -> None:
    command = Command('scene show', 'help', lambda parser: None, lambda args: 3, lambda r: View((str(r),)))
    assert command.json is False and command.view(command.run(None)).lines == ('3',)


def test_bad_input_is_an_error_and_an_interruption_is_ctrl_c() -> None:
    assert issubclass(BadInput, Exception) and not issubclass(BadInput, KeyboardInterrupt)
    assert issubclass(Interrupted, KeyboardInterrupt) and str(Interrupted('kept x')) == 'kept x'
