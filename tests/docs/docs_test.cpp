// The docs cannot drift from the code: every link of every Markdown file resolves (file and
// heading), every reference to a Markdown file from the sources resolves (comments, --help texts;
// a section is named by its anchor, file.md#anchor, never by a title in prose), and every example
// command of the guide and the README (```sh blocks) is accepted by the real command line:
// each runs with GYROCAL_CHECK_ONLY=1, which parses and checks it as usual and runs nothing
// (runtime/process_main.hpp), so an option that was renamed or a value out of range fails here.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "tests/docs/markdown.hpp"

namespace gyrocal::docs {
namespace {

namespace fs = std::filesystem;
const fs::path kRoot = GYROCAL_SOURCE_DIR;

std::string Read(const fs::path& p) {
    std::ifstream f(p);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

// Files under the source tree with one of `extensions` (build folders and .git skipped).
std::vector<fs::path> SourceFiles(const std::set<std::string>& extensions,
                                  const std::set<std::string>& names = {}) {
    std::vector<fs::path> out;
    for (auto it = fs::recursive_directory_iterator(kRoot);
         it != fs::recursive_directory_iterator(); ++it) {
        const std::string name = it->path().filename().string();
        if (it->is_directory() && (name.rfind("build", 0) == 0 || name[0] == '.' ||
                                   name == "Testing" || name == "reports")) {
            it.disable_recursion_pending();
            continue;
        }
        if (it->is_regular_file() &&
            (extensions.count(it->path().extension().string()) || names.count(name)))
            out.push_back(it->path());
    }
    std::sort(out.begin(), out.end());
    return out;
}

// "" when `target`, written in the file `from`, names an existing file and, after '#', one of
// its headings ("#anchor" alone: a heading of `from`); else what is wrong. A Markdown link is
// relative to its file's folder, as GitHub reads it; a reference from a source file may also be
// relative to the checkout's root (a comment names "processors/analysis/README.md#...").
std::string Resolve(const fs::path& from, const std::string& target, bool from_root_too) {
    const size_t hash = target.find('#');
    const std::string file = target.substr(0, hash);
    const std::string anchor = hash == std::string::npos ? "" : target.substr(hash + 1);
    fs::path path = file.empty() ? from : from.parent_path() / file;
    if (from_root_too && !fs::exists(path)) path = kRoot / file;
    if (!fs::exists(path)) return "no file " + file;
    if (anchor.empty() || path.extension() != ".md") return "";
    const std::vector<std::string> anchors = Anchors(Read(path));
    if (std::find(anchors.begin(), anchors.end(), anchor) == anchors.end())
        return "no heading with anchor #" + anchor + " in " + fs::relative(path, kRoot).string();
    return "";
}

TEST(Markdown, AnchorsLinksAndCommandsAsGitHubAndShReadThem) {
    const std::string md =
        "# A title: with (punctuation) and `code`\n## Twice\n## Twice\n"
        "See [x](other.md#a-b) and `[not](a link)`.\n"
        "```sh\n# comment\nP=\"--a 1 #2\"\nbuild/bin/gyrocal calibrate $P \\\n    --db x.db   # a "
        "comment\n```\n"
        "```text\nbuild/bin/gyrocal not a command\n```\n";
    EXPECT_THAT(Anchors(md),
                ::testing::ElementsAre("a-title-with-punctuation-and-code", "twice", "twice-1"));
    const auto links = Links(md);
    ASSERT_EQ(links.size(), 1u);
    EXPECT_EQ(links[0].target, "other.md#a-b");
    EXPECT_EQ(links[0].line, 4);
    const auto commands = ShellCommands(md);
    ASSERT_EQ(commands.size(), 2u);
    EXPECT_EQ(commands[0].text, "P=\"--a 1 #2\"");
    EXPECT_EQ(commands[1].text, "build/bin/gyrocal calibrate $P  --db x.db");
    EXPECT_EQ(commands[1].line, 8);
}

TEST(Docs, EveryLinkOfEveryMarkdownFileResolves) {
    const auto files = SourceFiles({".md"});
    ASSERT_GT(files.size(), 10u) << "the README and the folders' READMEs at least";
    int checked = 0;
    for (const fs::path& f : files) {
        for (const Link& l : Links(Read(f))) {
            if (l.target.rfind("http", 0) == 0 || l.target.rfind("mailto:", 0) == 0) continue;
            ++checked;
            EXPECT_EQ(Resolve(f, l.target, false), "")
                << fs::relative(f, kRoot).string() << ":" << l.line << ": (" << l.target << ")";
        }
    }
    EXPECT_GT(checked, 20) << "the README links to the guide";
}

TEST(Docs, EveryReferenceFromTheSourcesToAMarkdownFileResolves) {
    static const std::regex kRef(R"(([A-Za-z0-9_./-]*[A-Za-z0-9_-]\.md)(#[a-z0-9_-]+)?)");
    // A section named in prose (README, "Title") instead of by its anchor moves silently when the
    // text does; a string literal that merely ends after a file name (".md, " then a new line) is
    // not one.
    static const std::regex kProse(R"(README(?!\.md)|\.md,? "[A-Za-z])");
    const auto files =
        SourceFiles({".cpp", ".hpp", ".h", ".sh", ".cmake", ".lcm", ".py"}, {"CMakeLists.txt"});
    int checked = 0;
    for (const fs::path& f : files) {
        if (f.filename() == "docs_test.cpp") continue;
        std::istringstream in(Read(f));
        int n = 0;
        for (std::string line; std::getline(in, line);) {
            ++n;
            const std::string where = fs::relative(f, kRoot).string() + ":" + std::to_string(n);
            EXPECT_FALSE(std::regex_search(line, kProse))
                << where << ": name the document by its path and the section by its anchor "
                << "(docs/x.md#section): " << line;
            for (auto it = std::sregex_iterator(line.begin(), line.end(), kRef);
                 it != std::sregex_iterator(); ++it) {
                // The team's and the seed's notes (/work/shared: STYLE.md, DESIGN.md, METHOD.md)
                // are outside this repository; nothing here can check them.
                const std::string name = fs::path((*it)[1].str()).filename().string();
                if (name == "STYLE.md" || name == "DESIGN.md" || name == "METHOD.md") continue;
                ++checked;
                EXPECT_EQ(Resolve(f, (*it)[0].str(), true), "") << where << ": " << line;
            }
        }
    }
    EXPECT_GT(checked, 10);
}

TEST(Docs, EveryExampleCommandIsAcceptedByTheRealCommandLine) {
    std::vector<fs::path> pages = {kRoot / "README.md"};
    if (fs::exists(kRoot / "docs"))
        for (const auto& e : fs::directory_iterator(kRoot / "docs"))
            if (e.path().extension() == ".md") pages.push_back(e.path());
    const fs::path bin = GYROCAL_BIN;
    const fs::path scratch =
        fs::temp_directory_path() / ("gyrocal_docs_" + std::to_string(getpid()));
    fs::create_directories(scratch);
    // The examples are written from the checkout's root (tools/acceptance/limits.json, ...);
    // what they write goes to the scratch folder.
    fs::create_directory_symlink(kRoot / "tools", scratch / "tools");
    static const std::regex kInput(R"(--input[ =]([^ ]+))");
    static const std::regex kAssignment(R"(^[A-Z_][A-Z0-9_]*=)");
    static const std::regex kOurs(R"(^(build/bin/|tools/run\.sh\b))");
    int commands = 0;
    for (const fs::path& page : pages) {
        // One shell per page, in a scratch folder: its assignments hold for its later commands.
        std::string script = "export GYROCAL_CHECK_ONLY=1 GYROCAL_BUILD_DIR='" +
                             bin.parent_path().string() + "'\ncd '" + scratch.string() + "'\n";
        for (const Command& c : ShellCommands(Read(page))) {
            const std::string where =
                fs::relative(page, kRoot).string() + ":" + std::to_string(c.line);
            if (std::regex_search(c.text, kAssignment)) {
                script += c.text + "\n";
                continue;
            }
            ASSERT_TRUE(std::regex_search(c.text, kOurs))
                << where << ": a ```sh block holds gyrocal's own commands (build/bin/..., "
                << "tools/run.sh) and NAME=value lines only; put others in ```text: " << c.text;
            std::string line =
                std::regex_replace(c.text, std::regex("^build/bin/"), bin.string() + "/");
            line = std::regex_replace(line, std::regex("^tools/run\\.sh"),
                                      (kRoot / "tools/run.sh").string());
            script += line + " >/dev/null 2>\"$HOME_ERR\" || { echo '" + where + ": " +
                      std::regex_replace(c.text, std::regex("'"), "'\\''") +
                      "'; cat \"$HOME_ERR\"; exit 1; }\n";
            // An --input file is written by an earlier example (gyrocal-othersim --out, which
            // check-only does not run) or is the reader's own data: an empty one stands in, as
            // check-only reads no data.
            for (auto it = std::sregex_iterator(c.text.begin(), c.text.end(), kInput);
                 it != std::sregex_iterator(); ++it)
                std::ofstream(scratch / (*it)[1].str());
            ++commands;
        }
        const fs::path sh = scratch / "page.sh", out = scratch / "page.out";
        std::ofstream(sh) << "HOME_ERR='" << (scratch / "err.txt").string() << "'\n" << script;
        const int rc =
            std::system(("sh '" + sh.string() + "' > '" + out.string() + "' 2>&1").c_str());
        EXPECT_EQ(rc, 0) << Read(out);
    }
    std::printf("[ docs ] %d example commands on %zu pages accepted under GYROCAL_CHECK_ONLY=1\n",
                commands, pages.size());
    EXPECT_GE(commands, 30) << "the guide's examples";
    fs::remove_all(scratch);
}

// The mode the example commands run in: a valid command line exits 0 having done nothing (no
// file written, no database created), a bad one is refused as without it (exit 2).
TEST(CheckOnly, AValidCommandRunsNothingAndABadOneIsStillRefused) {
    const fs::path bin = GYROCAL_BIN;
    const fs::path dir = fs::temp_directory_path() / ("gyrocal_check_" + std::to_string(getpid()));
    fs::create_directories(dir);
    const auto run = [&](const std::string& args) {
        const int rc = std::system(("cd '" + dir.string() + "' && GYROCAL_CHECK_ONLY=1 '" +
                                    bin.string() + "/" + args + " >/dev/null 2>&1")
                                       .c_str());
        return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
    };
    EXPECT_EQ(run("gyrocal-othersim' --out data.csv --units 1"), 0);
    EXPECT_FALSE(fs::exists(dir / "data.csv")) << "check-only wrote the simulated data";
    EXPECT_EQ(run("gyrocal' runs --db runs.db"), 0);
    EXPECT_FALSE(fs::exists(dir / "runs.db")) << "check-only opened the database";
    EXPECT_EQ(run("gyrocal' calibrate --sensors 1 --db cal.db"), 0);
    EXPECT_FALSE(fs::exists(dir / "cal.db")) << "check-only started a calibration";
    EXPECT_EQ(run("gyrocal' calibrate --sensors 0"), 2);
    EXPECT_EQ(run("gyrocal' calibrate --no-such-option"), 2);
    EXPECT_EQ(run("gyrocal-othersim' --units 1"), 2) << "--out is required";
    EXPECT_EQ(run("gyrocal-plateau' --no-such-option"), 2);
    fs::remove_all(dir);
}

}  // namespace
}  // namespace gyrocal::docs
