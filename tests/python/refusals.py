"""The one-line refusal the module's archives give: the message of the qdmeta.InputError that
make() raises, checked to be one line."""

import pytest

import qdmeta


def refusal(make):
    with pytest.raises(qdmeta.InputError) as caught:
        make()
    message = str(caught.value)
    assert "\n" not in message, message
    return message
