"""i("name", key=...) with a literal name is checked when the grammar is loaded, not derived."""

import re

import pytest

from shapegen import parse_grammar
from shapegen.errors import GrammarError

TEMPLATE = """
@StartRule @Lot(4, 1)
Lot --> extrude(3) split(y) {{ 1 : Base | ~1 : Top }}
Base --> i("box")
Top --> case scope.sy > 100 : {call} else : Plain
"""


@pytest.mark.parametrize(
    ("call", "message", "column"),
    [
        ('i("arc")', "unknown primitive 'arc' (did you mean 'arch'?)", 31),
        ('i("arch", thicknes=0.2)', "has no parameter 'thicknes' (did you mean 'thickness'?)", 41),
    ],
)
def test_unknown_primitives_and_parameters_fail_at_load_time(call, message, column):
    # The case branch is never derived: only a load-time check can find the mistake.
    with pytest.raises(GrammarError, match=re.escape(message)) as caught:
        parse_grammar(TEMPLATE.format(call=call))
    assert caught.value.line == 5 and caught.value.column == column


def test_a_correct_call_loads_and_builds():
    grammar = parse_grammar(TEMPLATE.format(call='i("arch", thickness=0.2)'))
    assert len(grammar.build().blocks) == 2
