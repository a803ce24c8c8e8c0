#pragma once
// An SVG that gnuplot wrote, made fit to sit inline in an HTML page beside other figures: the XML
// prolog and any DOCTYPE removed; every id (gnuplot names its point symbols gpPt0.. and its canvas
// in every file alike) and every reference to one (#id in href / url()) prefixed, so several
// figures on one page do not resolve each other's symbols; the <title> set to the figure's
// title; the root tagged data-figure="<name>", role="img" and aria-label. No script is added,
// and a <script> element in the input is refused (a page that must work offline runs none).
#include <stdexcept>
#include <string>

namespace gyrocal::plot {

class SvgError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Throws SvgError when `svg` has no <svg> root or contains a script.
std::string InlineSvg(const std::string& svg, const std::string& name, const std::string& title);

// Text safe inside XML/HTML element content and attribute values (& < > " ' escaped).
std::string XmlEscape(const std::string& text);

}  // namespace gyrocal::plot
