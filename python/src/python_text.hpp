#pragma once
// A Python str as the UTF-8 text the C++ side keeps, or one line naming what holds it and why
// not: a lone surrogate (U+D800..U+DFFF) has no UTF-8 form (pybind11 would say only "Unable to
// cast"), and a NUL would end the text early in every message that quotes it.
#include <pybind11/pybind11.h>

#include <string>
#include <string_view>

namespace qdmeta::python {

// InputError "<what> holds ..." for such a str; a TypeError naming `what` for another type.
std::string checked_text(pybind11::handle value, std::string_view what);

}  // namespace qdmeta::python
