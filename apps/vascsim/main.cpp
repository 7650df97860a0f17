// vascsim command-line entry point; everything lives in vascsim::run_cli (src/vascsim/app/cli.cpp).
#include <iostream>
#include <string>
#include <vector>

#include "vascsim/app/cli.hpp"

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  return vascsim::run_cli(args, std::cout, std::cerr);
}
