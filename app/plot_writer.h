#pragma once
// Drawing PNG charts with gnuplot: data files and one script written into an output folder, one
// gnuplot run, every PNG drawn under its temporary name and renamed onto its final name
// (common/atomic_file.h).

#include <string>
#include <vector>

#include "common/atomic_file.h"

namespace ecpsim::app {

/// A string literal for a gnuplot script (single quotes; '' is a quote inside).
std::string GnuplotQuote(const std::string& text);

/// Collects data files and a gnuplot script in `dir`; Run() draws every PNG at once.
class PlotWriter {
 public:
  explicit PlotWriter(std::string dir);

  /// Writes the data file DIR/plot_NAME.dat now; returns its path quoted for the script.
  std::string Data(const std::string& name, const std::string& content);

  /// Starts the PNG DIR/NAME (e.g. "tbar_qz.png") of the given size in pixels.
  /// @throws InputError if something other than a regular file is at DIR/NAME.
  void BeginPng(const std::string& name, int width, int height);
  void EndPng();
  /// One line of gnuplot script.
  void Line(const std::string& line);

  /// Runs gnuplot, renames the PNGs into place, removes the data files and the script.
  /// @throws InputError if gnuplot fails (quoting its log) or a PNG cannot be renamed.
  /// @return the PNG paths.
  std::vector<std::string> Run();

 private:
  std::string dir_;
  std::string script_;
  std::vector<AtomicFile> pngs_;
  std::vector<std::string> temporaries_;
};

}  // namespace ecpsim::app
