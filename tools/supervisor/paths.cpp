#include "tools/supervisor/paths.hpp"

#include <cstdlib>
#include <filesystem>

namespace gyrocal::supervisor {

std::string ExecutableDir() {
    return std::filesystem::read_symlink("/proc/self/exe").parent_path().string();
}

std::string SiblingExecutable(const std::string& name) { return ExecutableDir() + "/" + name; }

std::string TypesJar() {
    if (const char* env = std::getenv("GYROCAL_TYPES_JAR"); env && *env) return env;
    return (std::filesystem::path(ExecutableDir()) / ".." / "java" / "gyrocal_types.jar")
        .lexically_normal()
        .string();
}

}  // namespace gyrocal::supervisor
