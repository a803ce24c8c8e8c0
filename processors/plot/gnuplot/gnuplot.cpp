#include "processors/plot/gnuplot/gnuplot.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "lcmtypes/launch/child_process.hpp"
#include "processors/plot/svg.hpp"

namespace gyrocal::plot::gnuplot {

namespace fs = std::filesystem;

namespace {

std::string Slurp(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

std::string LastLines(const std::string& text, int n) {
    std::vector<std::string> lines;
    std::istringstream s(text);
    for (std::string l; std::getline(s, l);)
        if (!l.empty()) lines.push_back(l);
    std::string out;
    for (size_t i = lines.size() > static_cast<size_t>(n) ? lines.size() - n : 0; i < lines.size();
         ++i)
        out += (out.empty() ? "" : " | ") + lines[i];
    return out;
}

// Runs `gnuplot scripts...` in `dir`, stdout and stderr into dir/gnuplot.log.
void Run(const std::string& gnuplot, const std::string& dir,
         const std::vector<std::string>& scripts) {
    const std::string log = (fs::path(dir) / "gnuplot.log").string();
    std::vector<std::string> args = {gnuplot};
    args.insert(args.end(), scripts.begin(), scripts.end());
    launch::ExitStatus status;
    try {
        status = launch::ChildProcess(args, launch::ChildOptions{log, log, dir, {}}).Wait();
    } catch (const std::runtime_error& e) {
        throw GnuplotError(e.what());
    }
    if (status.exited && status.code == 0) return;
    throw GnuplotError("gnuplot in " + dir + " failed (" + status.Describe() +
                       "): " + LastLines(Slurp(log), 3));
}

}  // namespace

std::vector<std::string> DrawInto(const std::string& gnuplot, const std::string& dir,
                                  const std::vector<Figure>& figures,
                                  const std::vector<Terminal>& terminals) {
    std::vector<std::string> scripts;
    for (const Figure& f : figures) {
        if (const std::string p = Validate(f); !p.empty()) throw GnuplotError(p);
        for (const File& file : Files(f, terminals)) {
            const fs::path path = fs::path(dir) / file.name;
            std::ofstream out(path, std::ios::binary | std::ios::trunc);
            out << file.text;
            if (!out.flush()) throw GnuplotError("cannot write " + path.string());
        }
        scripts.push_back(f.name + ".gp");
    }
    if (scripts.empty()) return {};
    Run(gnuplot, dir, scripts);
    std::vector<std::string> pictures;
    for (const Figure& f : figures)
        for (Terminal t : terminals) {
            const fs::path path = fs::path(dir) / (f.name + "." + Extension(t));
            std::error_code ec;
            if (!fs::exists(path, ec) || fs::file_size(path, ec) == 0)
                throw GnuplotError("gnuplot did not write " + path.string());
            pictures.push_back(path.string());
        }
    return pictures;
}

std::vector<std::string> DrawInlineSvgs(const std::string& gnuplot,
                                        const std::vector<Figure>& figures) {
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/gyrocal-figures-XXXXXX";
    if (!::mkdtemp(pattern.data())) throw GnuplotError("cannot create a directory like " + pattern);
    struct Cleanup {
        std::string dir;
        ~Cleanup() {
            std::error_code ec;
            fs::remove_all(dir, ec);
        }
    } cleanup{pattern};
    const std::vector<std::string> pictures = DrawInto(gnuplot, pattern, figures, {Terminal::kSvg});
    std::vector<std::string> out;
    for (size_t i = 0; i < figures.size(); ++i)
        out.push_back(InlineSvg(Slurp(pictures[i]), figures[i].name, figures[i].title));
    return out;
}

}  // namespace gyrocal::plot::gnuplot
