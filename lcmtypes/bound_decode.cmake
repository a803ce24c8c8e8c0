# Run after lcm-gen (cmake -DDIR=<folder of generated .hpp> -P bound_decode.cmake).
#
# Why: lcm-gen 1.3.1's C++ decode trusts the length fields of a received message. It sizes an
# array with std::vector::resize(length) BEFORE checking that the payload holds that many
# elements, and it assigns a string of (length - 1) bytes without checking length >= 1. So a
# 150-byte coeff_set_t whose int32 num_plateaus says 2^31-1 made every receiver allocate and
# zero 16 GB, and a negative length threw std::length_error (found by the fuzz harnesses,
# tests/fuzz). Every element takes at least one byte of the payload, so a length that is
# negative or larger than the bytes left cannot be valid; the guards below make decode() return
# -1 for it, as it does for any other short payload. Valid messages decode exactly as before.
#
# The rewrite is checked: a generated .resize( or string length test of a form this script does
# not know stops the build, so a different lcm-gen cannot silently lose the guards.
cmake_policy(VERSION 3.25)
file(GLOB headers ${DIR}/*.hpp)
foreach(header ${headers})
  file(READ ${header} text)
  if(text MATCHES "gyrocal: bounded decode")
    continue()  # already rewritten (lcm-gen did not run again)
  endif()
  # Arrays: "this->X.resize(this->N);" and "this->X[a0].resize(this->N);".
  string(REGEX REPLACE
    "\n( *)(this->[A-Za-z0-9_]+(\\[a[0-9]+\\])?\\.resize\\(this->([A-Za-z0-9_]+)\\);)"
    "\n\\1if (this->\\4 < 0 || this->\\4 > maxlen - pos) return -1;  // gyrocal: bounded decode\n\\1\\2"
    text "${text}")
  # Strings: "if(__X > maxlen - pos) return -1;" (X = name_len__ or elem_len).
  string(REGEX REPLACE
    "if\\(__([A-Za-z0-9_]+) > maxlen - pos\\) return -1;"
    "if(__\\1 < 1 || __\\1 > maxlen - pos) return -1;  // gyrocal: bounded decode"
    text "${text}")
  string(REGEX MATCHALL "\\.resize\\(" resizes "${text}")
  string(REGEX MATCHALL "< 0 \\|\\| this->[A-Za-z0-9_]+ > maxlen - pos\\) return -1" guards "${text}")
  list(LENGTH resizes n_resizes)
  list(LENGTH guards n_guards)
  string(REGEX MATCHALL "_len(__)? > maxlen - pos" strings "${text}")
  string(REGEX MATCHALL "_len(__)? < 1 \\|\\|" string_guards "${text}")
  list(LENGTH strings n_strings)
  list(LENGTH string_guards n_string_guards)
  if(NOT n_resizes EQUAL n_guards OR NOT n_strings EQUAL n_string_guards)
    message(FATAL_ERROR "bound_decode.cmake: ${header}: ${n_resizes} resize() with ${n_guards} "
                        "guards, ${n_strings} string lengths with ${n_string_guards} guards: "
                        "lcm-gen wrote a form this script does not know; update its patterns")
  endif()
  file(WRITE ${header} "${text}")
endforeach()
