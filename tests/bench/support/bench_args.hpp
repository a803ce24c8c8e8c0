#pragma once
// The positional arguments of a benchmark (`gyrocal_bench_analysis 20`): whole numbers with a
// default when left out, and the usage line with exit code 2 when one is out of its range.
// Header-only like machine.hpp.
#include <cstdio>
#include <cstdlib>

namespace gyrocal::bench {

// argv[index] as a whole number (std::atoi: text that is no number reads as 0), `fallback` when
// the argument is not given.
inline int IntArg(int argc, char** argv, int index, int fallback) {
    return argc > index ? std::atoi(argv[index]) : fallback;
}

// Prints "usage: <program> <args>" on stderr and returns 2, a benchmark's exit code for bad
// arguments.
inline int Usage(char** argv, const char* args) {
    std::fprintf(stderr, "usage: %s %s\n", argv[0], args);
    return 2;
}

}  // namespace gyrocal::bench
