#pragma once
// Where the gyrocal executables and the lcm-spy types jar are: beside this executable (the
// build's bin/ folder), so a build tree runs without installation.
#include <string>

namespace gyrocal::supervisor {

std::string ExecutableDir();                             // folder of /proc/self/exe
std::string SiblingExecutable(const std::string& name);  // ExecutableDir()/name
std::string TypesJar();  // $GYROCAL_TYPES_JAR, else <bin>/../java/gyrocal_types.jar

}  // namespace gyrocal::supervisor
