#pragma once
// Where the files that ship with vascsim are: the bundled scenes (scenes/), data (data/, e.g. the AHP
// judgements) and the plot scripts the experiments run (scripts/). A build tree finds them in the source tree
// it was built from; an installed vascsim in <prefix>/share/vascsim (docs/api.md, "Install layout"), found
// relative to the installed library first, so a prefix moved as a whole still works.

#include <filesystem>
#include <string>
#include <vector>

namespace vascsim {

/// The folders searched for bundled files, in order: $VASCSIM_DATA_DIR (when set); the share/vascsim folder
/// next to the installed library; the source tree when this library is the one in its build tree; the
/// share/vascsim folder of the configured install prefix; the source tree.
std::vector<std::filesystem::path> bundled_roots();

/// `relative` (e.g. "scripts/plot_ahp.py", "scenes") in the first of bundled_roots() that has it; when none
/// has it, under bundled_root() (so a message names a path where the user would look for it).
std::filesystem::path bundled_file(const std::string& relative);

/// The root bundled_file() takes files from: the first of bundled_roots() that has scenes/ and scripts/.
std::filesystem::path bundled_root();

}  // namespace vascsim
