#pragma once
// Runs gnuplot (Debian package gnuplot-nox) on figures of gyrocal_plot: the files go into a
// directory, one gnuplot process runs every script there (scripts name their files relative to
// it), and the pictures are checked to exist. No shell is involved (gnuplot is a ChildProcess of
// lcmtypes/launch); gnuplot's own messages go to <dir>/gnuplot.log and the last of them into the
// error.
#include <stdexcept>
#include <string>
#include <vector>

#include "lcmtypes/launch/child_process.hpp"
#include "processors/plot/figure.hpp"

namespace gyrocal::plot::gnuplot {

class GnuplotError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Full path of `program` found on $PATH; "" when absent: the project's one PATH search
// (lcmtypes/launch), by the name its callers here have always used.
using ::gyrocal::launch::FindOnPath;

// What to tell someone without gnuplot.
inline constexpr const char* kGnuplotMissing =
    "needs gnuplot on PATH (install the Debian package gnuplot-nox)";

// Writes every figure's files into `dir` (which must exist) and runs `gnuplot` there once on all
// the scripts. Returns the paths of the pictures, figure by figure in terminal order. Throws
// GnuplotError naming the file or the script on a problem (a figure that is not drawable, a
// file that cannot be written, gnuplot failing or not writing a picture).
std::vector<std::string> DrawInto(const std::string& gnuplot, const std::string& dir,
                                  const std::vector<Figure>& figures,
                                  const std::vector<Terminal>& terminals);

// Draws the figures as SVG in a fresh directory under $TMPDIR (removed afterwards) and returns
// each picture made fit for inlining in an HTML page (svg.hpp: InlineSvg with the figure's name
// and title), in the order of `figures`. Throws GnuplotError or SvgError.
std::vector<std::string> DrawInlineSvgs(const std::string& gnuplot,
                                        const std::vector<Figure>& figures);

}  // namespace gyrocal::plot::gnuplot
