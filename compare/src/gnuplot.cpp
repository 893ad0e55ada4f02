#include "gnuplot.hpp"

#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include "camplace/core/files.hpp"

namespace camplace::compare::detail {

void gnuplot_png(const std::string& png, const std::string& script, int width, int height) {
  namespace fs = std::filesystem;
  fs::path gp = png;
  gp.replace_extension(".gp");
  const fs::path tmp_png = png + ".part";
  const std::string full = "set terminal pngcairo size " + std::to_string(width) + "," +
                           std::to_string(height) + " font 'DejaVu Sans,10'\n" +
                           "set output '" + tmp_png.string() + "'\n" + script + "\nunset output\n";
  core::write_file_atomically(gp.string(), full);
  const std::string cmd = "gnuplot '" + gp.string() + "' 2>'" + png + ".log'";
  if (std::system(cmd.c_str()) != 0) {
    throw std::runtime_error("gnuplot failed on " + gp.string() + " (see " + png + ".log)");
  }
  std::error_code ec;
  fs::remove(png + ".log", ec);
  fs::rename(tmp_png, png);
}

}  // namespace camplace::compare::detail
