#pragma once
// Reading the project's Markdown as the docs tests need it: headings and their anchors (GitHub's
// rule), links, and the example commands of ```sh blocks.
#include <string>
#include <vector>

namespace gyrocal::docs {

// GitHub's anchor of a heading: lower case, punctuation dropped (letters, digits, spaces,
// '-' and '_' kept), spaces to '-'.
std::string Slug(const std::string& heading);

// The anchors of every heading of `markdown` (ATX '#' headings outside code blocks); a repeated
// heading gets "-1", "-2", ... as on GitHub.
std::vector<std::string> Anchors(const std::string& markdown);

struct Link {
    int line = 0;
    std::string target;  // as written: "path", "path#anchor", "#anchor", "https://..."
};
// Every inline link [text](target) outside code blocks and code spans.
std::vector<Link> Links(const std::string& markdown);

struct Command {
    int line = 0;      // of its first line
    std::string text;  // continuation lines ("\" at the end) joined
};
// The lines of every ```sh block: commands, variable assignments (NAME=...), no comments (whole
// lines or trailing "# ...").
std::vector<Command> ShellCommands(const std::string& markdown);

}  // namespace gyrocal::docs
