// The text overlay: time, contact modes and solver iterations on a light panel, top left.

#include <algorithm>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "render/draw_context.h"

namespace ecpsim::render {
namespace {

// the panel's distance from the image corner and its padding, pixels at pixel_scale 1
constexpr double kMargin = 8.0;
constexpr double kPadding = 5.0;

}  // namespace

void DrawTextOverlay(const FrameInput& frame, DrawContext& context) {
  if (!frame.show.text) return;
  std::vector<std::string> lines;
  if (!frame.title.empty()) lines.push_back(frame.title);
  lines.push_back(fmt::format("t = {:.3f} s", frame.time));
  if (!frame.contacts.empty()) {
    std::string modes;
    for (const ContactVisual& contact : frame.contacts) {
      modes +=
          (modes.empty() ? "" : ", ") + std::string(geometry::ContactModeName(contact.patch.mode));
    }
    lines.push_back("contact: " + modes);
  }
  if (!frame.model.empty()) lines.push_back("model: " + frame.model);
  if (frame.iterations >= 0) {
    lines.push_back(
        fmt::format("solver: {} iteration{}", frame.iterations, frame.iterations == 1 ? "" : "s"));
  }

  // a light panel behind the lines keeps them legible over the grid
  const double s = context.pixel_scale;
  const double margin = kMargin * s, pad = kPadding * s;
  double width = 0;
  for (const auto& line : lines) width = std::max(width, context.font.TextWidth(line));
  const double height = lines.size() * context.font.line_height();
  OverlayBatch panel, text;
  panel.Rectangle(margin, margin, margin + width + 2 * pad, margin + height + 2 * pad,
                  palette::kPanel);
  double baseline = margin + pad + context.font.ascender();
  for (const auto& line : lines) {
    context.font.AddText(text, line, margin + pad, baseline, palette::kText);
    baseline += context.font.line_height();
  }
  UseOverlayProgram(context, false);
  context.overlay.Draw(panel);
  UseOverlayProgram(context, true);
  context.overlay.Draw(text, context.font.texture());
}

}  // namespace ecpsim::render
