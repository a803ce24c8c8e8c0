#pragma once
// The header block every benchmark prints first: when it ran (UTC), on which commit of the source
// tree, with which command, and on which machine and at what load. A figure quoted in the guide is
// only worth something with these beside it, and the command tells a reader how to get it again.
//
// The commit is read at run time from the source tree the benchmark was built from (its path is
// compiled in as GYROCAL_SOURCE_DIR): `git rev-parse HEAD`, "+dirty" when a tracked file differs
// from it (untracked files are not counted, as with `git describe --dirty`), and
// "unknown (not a git checkout: DIR)" when git cannot read the tree there (a copied tree, an
// installed one, or no git on the machine: "unknown (git not found)").
#include <string>
#include <utility>
#include <vector>

namespace gyrocal::bench {

// One line of the block: a key ("date", "commit", ...) and its value, in printing order. The keys
// are also the names given to Google Benchmark's custom context.
using ContextField = std::pair<std::string, std::string>;

// The commit of the tree at `source_dir` as described above. Runs git (two short child processes).
std::string SourceCommit(const std::string& source_dir);

// The fields of the block, for the benchmark started as argv[0..argc-1], reading the tree at
// `source_dir`: date, command, commit, host, cpu, memory, kernel, load.
std::vector<ContextField> ReadContext(int argc, char** argv, const std::string& source_dir);

// As above for the source tree this benchmark was built from.
std::vector<ContextField> ReadContext(int argc, char** argv);

// The block as printed: one "key:    value" line per field (values aligned), ending in '\n'.
std::string FormatContext(const std::vector<ContextField>& fields);

// Prints FormatContext(ReadContext(argc, argv)) on stdout and flushes it (a benchmark's children
// then write after it). Call first in main.
void PrintContext(int argc, char** argv);

}  // namespace gyrocal::bench
