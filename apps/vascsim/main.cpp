// vascsim command-line entry point; everything lives in vascsim::run_cli (src/vascsim/app/cli.cpp), plus the
// viewer's `view` command and the pictures of `navigate --pictures` when it is built
// (src/vascsim/viewer/view_command.hpp, navigation_pictures.hpp).
#include <iostream>
#include <string>
#include <vector>

#include "vascsim/app/cli.hpp"
#include "vascsim/core/blas_control.hpp"
#ifdef VASCSIM_HAS_VIEWER
#include "vascsim/viewer/navigation_pictures.hpp"
#include "vascsim/viewer/view_command.hpp"
#endif

int main(int argc, char** argv) {
  vascsim::restart_with_blas_core(argv);  // OpenBLAS's own kernels on CPUs newer than its table
  std::vector<std::string> args(argv + 1, argv + argc);
  std::vector<vascsim::CommandAdder> extra;
#ifdef VASCSIM_HAS_VIEWER
  extra.push_back(&vascsim::viewer::add_view_command);
  extra.push_back(&vascsim::viewer::install_navigation_pictures);
#endif
  return vascsim::run_cli(args, std::cout, std::cerr, extra);
}
