#include "pipeline/stages/stage_inputs.hpp"

#include <filesystem>

#include "config/error.hpp"

namespace rangecal {

void require_stage_output(const std::string& path, const char* stage) {
  if (!std::filesystem::exists(path))
    throw_input_error(
        path, 0, "",
        std::string("missing; run the ") + stage + " stage first (rangecal " + stage + " CONFIG)");
}

}  // namespace rangecal
