"""The keyword options are every field of RegistrationOptions and ExpertOptions, with the same
defaults: checked against include/ppcr/options.hpp itself, read as text."""
import re

import pytest

import ppcr
from conftest import REPO

# The header's spellings of the enums' defaults and of kAutomatic, as the module spells them.
WORDS = {"ErrorModel::kPlane": "plane", "ErrorModel::kPoint": "point",
         "WeightModel::kStudentT": "student_t", "WeightModel::kGaussian": "gaussian",
         "ScaleMode::kEM": "em", "ScaleMode::kRaw": "raw", "ScaleMode::kFixed": "fixed",
         "kCriterionCostDrop": ["cost_drop"], "kAutomatic": -1.0, "kAutomaticRadius": 0.0,
         "static_cast<int>(kAutomatic)": -1, "true": True, "false": False}


def header_fields():
    """{field: default} of the two option structs, from their member declarations."""
    text = (REPO / "include" / "ppcr" / "options.hpp").read_text()
    fields = {}
    for struct in ("ExpertOptions", "RegistrationOptions"):
        body = re.search(r"struct %s \{(.*?)\n\};" % struct, text, re.S).group(1)
        for name, default in re.findall(
                r"^ +(?!static )(?!//)\S.*? (\w+)(?: = ([^;]+))?;[ \t]*(?://.*)?$", body, re.M):
            fields[name] = default
    return fields


def test_every_field_with_its_default():
    fields = header_fields()
    # on_iteration is register()'s own argument; expert's fields are flattened.
    assert "on_iteration" in fields and "expert" in fields and "radius" in fields
    del fields["on_iteration"], fields["expert"]
    defaults = ppcr.default_options()
    assert set(defaults) == set(fields)
    for name, text in fields.items():
        expected = WORDS[text] if text in WORDS else float(text)
        assert defaults[name] == expected, name


def test_defaults_reach_register_unchanged():
    """Passing every default explicitly changes nothing (the same pose, to the bit)."""
    from support import blob
    source, target = blob(1500, seed=7), blob(1500, seed=8)
    implicit = ppcr.register(source, target, radius=0.1)
    explicit = ppcr.register(source, target, **dict(ppcr.default_options(), radius=0.1))
    assert (explicit.transformation == implicit.transformation).all()
    assert explicit.iterations == implicit.iterations


def test_docstring_lists_every_option():
    for name, value in ppcr.default_options().items():
        assert f"  {name}={value!r}: " in ppcr.register.__doc__, name
