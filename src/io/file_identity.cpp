#include "io/file_identity.h"

#include <fmt/format.h>

#include <system_error>

#include "model/run_options.h"

namespace cmcsurf {

void check_outputs_are_not_inputs(const std::vector<FileRole>& reads,
                                  const std::vector<FileRole>& writes) {
  for (const FileRole& w : writes)
    for (const FileRole& r : reads) {
      std::error_code ec;  // a missing file (or an unreadable one) is not the same file
      if (!std::filesystem::equivalent(w.path, r.path, ec) || ec) continue;
      throw OptionError(fmt::format(
          "{}: '{}' would overwrite {} '{}' (the same file); write the output elsewhere",
          w.role, w.path.string(), r.role, r.path.string()));
    }
}

}  // namespace cmcsurf
