#include "app/plot_writer.h"

#include <filesystem>

#include <fmt/format.h>

#include "app/atomic_file.h"
#include "app/gnuplot_process.h"
#include "common/errors.h"

namespace ecpsim::app {

namespace fs = std::filesystem;

std::string GnuplotQuote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) {
    quoted += c;
    if (c == '\'') quoted += '\'';
  }
  return quoted + "'";
}

PlotWriter::PlotWriter(std::string dir) : dir_(std::move(dir)) {
  script_ = "set terminal pngcairo size 1200,800 font 'DejaVu Sans,11'\nset grid\nset key top right\n";
}

std::string PlotWriter::Data(const std::string& name, const std::string& content) {
  const std::string path = (fs::path(dir_) / ("plot_" + name + ".dat")).string();
  WriteFileAtomically(path, content);
  temporaries_.push_back(path);
  return GnuplotQuote(path);
}

void PlotWriter::BeginPng(const std::string& name, int width, int height) {
  const std::string path = (fs::path(dir_) / name).string();
  pngs_.push_back(path);
  script_ += fmt::format("set terminal pngcairo size {},{} font 'DejaVu Sans,11'\n", width, height);
  script_ += fmt::format("set output {}\n", GnuplotQuote(path + ".partial"));
}

void PlotWriter::EndPng() { script_ += "unset multiplot\nset output\nreset\nset grid\n"; }

void PlotWriter::Line(const std::string& line) { script_ += line + "\n"; }

std::vector<std::string> PlotWriter::Run() {
  const std::string script = (fs::path(dir_) / "plot_script.gp").string();
  const std::string log = (fs::path(dir_) / "plot_gnuplot.log").string();
  WriteFileAtomically(script, script_);
  RunGnuplot(script, log);
  for (const std::string& png : pngs_) {
    std::error_code error;
    fs::rename(png + ".partial", png, error);
    if (error) {
      throw InputError(fmt::format("{}.partial: cannot rename it to {} ({}); gnuplot's log: {}",
                                   png, png, error.message(), log));
    }
  }
  // the data and the script were only gnuplot's input
  std::error_code ignored;
  for (const std::string& path : temporaries_) fs::remove(path, ignored);
  fs::remove(script, ignored);
  fs::remove(log, ignored);
  return pngs_;
}

}  // namespace ecpsim::app
