#pragma once
// Plots through gnuplot (Debian package gnuplot-nox): data and script files are written
// beside the PNG, so every figure can be regenerated and inspected. Private to compare.
#include <string>

namespace camplace::compare::detail {

/// Runs `script` (gnuplot commands after the terminal/output lines) writing `png`. The script
/// is kept as <png without .png>.gp. Throws std::runtime_error when gnuplot fails.
void gnuplot_png(const std::string& png, const std::string& script, int width = 800,
                 int height = 560);

/// `text` as a gnuplot single-quoted string ('it''s'), e.g. a file name in a plot command.
std::string gnuplot_string(const std::string& text);

}  // namespace camplace::compare::detail
