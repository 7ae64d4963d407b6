// A command's outputs may not overwrite its own inputs (it would read what it is writing):
// files are compared by identity (device and inode, std::filesystem::equivalent), not by
// name, so a symlink, a hard link or another spelling of a path ("./x", "d/../x") is caught.
// Used by `mesh`, `scaffold` and `graded` before any work.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace cmcsurf {

// A file a command reads or writes, with what the user calls it ("--from", "--out's report").
struct FileRole {
  std::filesystem::path path;
  std::string role;
};

// Throws OptionError (model/run_options.h) naming both when a file in `writes` is the same
// file as one in `reads`. A file that does not exist is no input's: it passes.
void check_outputs_are_not_inputs(const std::vector<FileRole>& reads,
                                  const std::vector<FileRole>& writes);

}  // namespace cmcsurf
