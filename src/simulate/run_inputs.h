#pragma once
/// What a run read and how to run it again (pipeline/resolved.h collects them): the sha256 of
/// every input file, and the resolved/ tree a run writes.
#include <string>
#include <utility>
#include <vector>

namespace sscs {

struct InputFile {
  std::string path;  ///< as it was read
  std::string sha256;
};

struct RunInputs {
  std::vector<InputFile> files;
  /// Files of resolved/: a path relative to the run folder ("resolved/vault.yaml") and its bytes.
  std::vector<std::pair<std::string, std::string>> resolved;
  /// Inputs resolved/ could not hold (an absolute path, or one outside its library folder):
  /// a rerun reads them from where they are.
  std::vector<std::string> not_copied;
};

}  // namespace sscs
