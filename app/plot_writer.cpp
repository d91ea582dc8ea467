#include "app/plot_writer.h"

#include <filesystem>

#include <fmt/format.h>

#include "app/gnuplot_process.h"
#include "common/atomic_file.h"

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
  script_ =
      "set terminal pngcairo size 1200,800 font 'DejaVu Sans,11'\nset grid\nset key top right\n";
}

std::string PlotWriter::Data(const std::string& name, const std::string& content) {
  const std::string path = (fs::path(dir_) / ("plot_" + name + ".dat")).string();
  WriteFileAtomically(path, content);
  temporaries_.push_back(path);
  return GnuplotQuote(path);
}

void PlotWriter::BeginPng(const std::string& name, int width, int height) {
  pngs_.emplace_back((fs::path(dir_) / name).string());
  script_ += fmt::format("set terminal pngcairo size {},{} font 'DejaVu Sans,11'\n", width, height);
  script_ += fmt::format("set output {}\n", GnuplotQuote(pngs_.back().temp_path()));
}

void PlotWriter::EndPng() { script_ += "unset multiplot\nset output\nreset\nset grid\n"; }

void PlotWriter::Line(const std::string& line) { script_ += line + "\n"; }

std::vector<std::string> PlotWriter::Run() {
  const std::string script = (fs::path(dir_) / "plot_script.gp").string();
  const std::string log = (fs::path(dir_) / "plot_gnuplot.log").string();
  WriteFileAtomically(script, script_);
  RunGnuplot(script, log);
  std::vector<std::string> paths;
  for (AtomicFile& png : pngs_) {
    png.Commit();
    paths.push_back(png.path());
  }
  // the data and the script were only gnuplot's input
  std::error_code ignored;
  for (const std::string& path : temporaries_) fs::remove(path, ignored);
  fs::remove(script, ignored);
  fs::remove(log, ignored);
  return paths;
}

}  // namespace ecpsim::app
