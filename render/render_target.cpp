#include "render/render_target.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "common/errors.h"
#include "render/gl_api.h"

namespace ecpsim::render {
namespace {

// the supported supersampling factors: integers, whose footprints are whole blocks, and 1.5,
// whose 3 × 3 drawing blocks split into 2 × 2 image pixels; beyond 4 × 4 supersamples the cost
// grows faster than the edges improve
constexpr double kSupersampleFactors[] = {1, 1.5, 2, 3, 4};

bool IsSupportedFactor(double supersample) {
  return std::find(std::begin(kSupersampleFactors), std::end(kSupersampleFactors), supersample) !=
         std::end(kSupersampleFactors);
}

// drawing pixels along an image side of `pixels` at `supersample`, rounded up so that the last
// image pixel's footprint is inside the drawing
int DrawingSize(int pixels, double supersample) {
  return static_cast<int>(std::ceil(pixels * supersample));
}

void CheckComplete(const char* which, int width, int height, int samples) {
  const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    throw std::runtime_error(fmt::format(
        "the {} framebuffer of {}x{} pixels with {} samples is incomplete (status 0x{:x})", which,
        width, height, samples, status));
  }
}

// Each image pixel (w × h, 3 bytes in the drawing's order, top row first) is the rounded mean
// of its S × S drawing pixels in `bottom_up` (4 bytes, bottom row first). S is a template
// parameter so the loops unroll and vectorize, and the division by S² becomes a multiply (an
// integer division per byte would cost ~20 ms per 1280×720 frame).
template <int S>
void Downsample(const std::uint8_t* bottom_up, int w, int h, std::uint8_t* pixels) {
  constexpr int kCount = S * S;
  const size_t row_bytes = static_cast<size_t>(w) * S * 4;
  const int drawing_rows = h * S;
  if constexpr (S == 2) {
    // the default: one pass over each pair of rows, no accumulator
    for (int y = 0; y < h; ++y) {
      const std::uint8_t* a = bottom_up + (drawing_rows - 1 - 2 * y) * row_bytes;
      const std::uint8_t* b = a - row_bytes;
      std::uint8_t* dst = pixels + static_cast<size_t>(y) * w * 3;
      for (int x = 0; x < w; ++x) {
        for (int c = 0; c < 3; ++c) {
          dst[3 * x + c] = static_cast<std::uint8_t>(
              (a[8 * x + c] + a[8 * x + 4 + c] + b[8 * x + c] + b[8 * x + 4 + c] + 2) >> 2);
        }
      }
    }
    return;
  }
  std::vector<int> sums(static_cast<size_t>(w) * 3);
  for (int y = 0; y < h; ++y) {
    std::fill(sums.begin(), sums.end(), kCount / 2);
    int* sum = sums.data();
    for (int r = 0; r < S; ++r) {
      const std::uint8_t* src = bottom_up + (drawing_rows - 1 - (y * S + r)) * row_bytes;
      for (int x = 0; x < w; ++x) {
        for (int c = 0; c < S; ++c) {
          const std::uint8_t* p = src + 4 * (x * S + c);
          sum[3 * x] += p[0];
          sum[3 * x + 1] += p[1];
          sum[3 * x + 2] += p[2];
        }
      }
    }
    std::uint8_t* dst = pixels + static_cast<size_t>(y) * w * 3;
    for (int i = 0; i < 3 * w; ++i) dst[i] = static_cast<std::uint8_t>(sum[i] / kCount);
  }
}

// 1.5× supersampling: image pixel i spans drawing pixels [1.5 i, 1.5 i + 1.5), i.e. all of one
// drawing pixel and half of a neighbour: for even i = 2k drawing pixels 3k (weight 2) and
// 3k + 1 (weight 1); for odd i = 2k + 1 drawing pixels 3k + 1 (1) and 3k + 2 (2). The 2-D
// weights are products (4, 2, 2, 1), summing to 9; the rounded division by the constant 9
// compiles to a multiply.
struct Tap {
  int first, second;  // drawing pixel indices
  int first_weight, second_weight;
};

Tap ThreeHalvesTap(int i) {
  const int k = i / 2;
  return i % 2 == 0 ? Tap{3 * k, 3 * k + 1, 2, 1} : Tap{3 * k + 1, 3 * k + 2, 1, 2};
}

// x / 9 for x ≤ 2299 (9 × 255 + 4) as the high half of a 16 × 16-bit product, one SIMD
// instruction (pmulhuw) where a 32-bit division by a constant does not vectorize on baseline
// x86-64: 7282 / 2^16 exceeds 1/9 by 3.4e-6, so for x ≤ 2299 the product is at most 0.008 above
// x / 9, whose fractional part is at most 8/9: the floor is the same
inline std::uint8_t DivideByNine(std::uint16_t x) {
  return static_cast<std::uint8_t>((static_cast<std::uint32_t>(x) * 7282u) >> 16);
}

// Separable and vectorizable: each image row's two weighted drawing rows are summed into
// `column_sums` (16-bit per channel); then every byte position i gets both horizontal taps,
// left[i] = (2 v[i] + v[i + 4] + 4) / 9 and right[i] = (v[i] + 2 v[i + 4] + 4) / 9, in loops
// over contiguous arrays that the compiler turns into SIMD (the division by the constant 9 into
// a multiply-high); finally image pixel 2k takes left at drawing pixel 3k and pixel 2k + 1
// right at drawing pixel 3k + 1, 4-byte copies whose fourth byte the next copy overwrites.
// Computing the taps at every position wastes 3 in 4 of them but costs less than the scalar
// per-pixel loop it replaced (~3 → ~1.5 ms per 1280×720 frame); the result is the same to the
// bit (RenderTarget.ThreeHalves* compare it with the area-weighted mean).
void DownsampleThreeHalves(const std::uint8_t* bottom_up, int drawing_width, int drawing_height,
                           int w, int h, std::uint8_t* pixels) {
  const size_t row_bytes = static_cast<size_t>(drawing_width) * 4;
  // weighted sums of ≤ 9 bytes fit 16 bits (9 × 255 = 2295)
  std::vector<std::uint16_t> column_sums(row_bytes);
  std::vector<std::uint8_t> left(row_bytes), right(row_bytes);
  const size_t taps = row_bytes - 4;  // positions with a right-hand neighbour pixel
  const int pairs = w / 2;            // whole 3-pixel runs
  for (int y = 0; y < h; ++y) {
    // image rows run top down; drawing rows bottom up
    const Tap rows = ThreeHalvesTap(y);
    const std::uint8_t* a = bottom_up + (drawing_height - 1 - rows.first) * row_bytes;
    const std::uint8_t* b = bottom_up + (drawing_height - 1 - rows.second) * row_bytes;
    const std::uint16_t wa = static_cast<std::uint16_t>(rows.first_weight);
    const std::uint16_t wb = static_cast<std::uint16_t>(rows.second_weight);
    std::uint16_t* v = column_sums.data();
    for (size_t i = 0; i < row_bytes; ++i) {
      v[i] = static_cast<std::uint16_t>(wa * a[i] + wb * b[i]);
    }
    std::uint8_t* l = left.data();
    std::uint8_t* r = right.data();
    for (size_t i = 0; i < taps; ++i) {
      l[i] = DivideByNine(static_cast<std::uint16_t>(2 * v[i] + v[i + 4] + 4));
      r[i] = DivideByNine(static_cast<std::uint16_t>(v[i] + 2 * v[i + 4] + 4));
    }
    std::uint8_t* dst = pixels + static_cast<size_t>(y) * w * 3;
    // all but the last pair with 4-byte copies (the 4th byte lands on the next pixel's first)
    for (int k = 0; k + 1 < pairs; ++k) {
      std::memcpy(dst + 6 * k, l + 12 * k, 4);
      std::memcpy(dst + 6 * k + 3, r + 12 * k + 4, 4);
    }
    if (pairs > 0) {
      const int k = pairs - 1;
      std::memcpy(dst + 6 * k, l + 12 * k, 3);
      std::memcpy(dst + 6 * k + 3, r + 12 * k + 4, 3);
    }
    // an odd width's last pixel: drawing pixels 3k (weight 2) and 3k + 1 (weight 1)
    if (w % 2 != 0) {
      const Tap t = ThreeHalvesTap(w - 1);
      for (int c = 0; c < 3; ++c) {
        dst[3 * (w - 1) + c] = static_cast<std::uint8_t>(
            (t.first_weight * v[4 * t.first + c] + t.second_weight * v[4 * t.second + c] + 4) / 9);
      }
    }
  }
}

// the image (w × h, top row first, 3 bytes a pixel in the drawing's order) of the drawing
// `bottom_up` (drawing_width × drawing_height, 4 bytes a pixel, bottom row first)
void DownsampleBy(double supersample, const std::uint8_t* bottom_up, int drawing_width,
                  int drawing_height, int w, int h, std::uint8_t* pixels) {
  if (supersample == 1.5) {
    DownsampleThreeHalves(bottom_up, drawing_width, drawing_height, w, h, pixels);
  } else if (supersample == 1) {
    Downsample<1>(bottom_up, w, h, pixels);
  } else if (supersample == 2) {
    Downsample<2>(bottom_up, w, h, pixels);
  } else if (supersample == 3) {
    Downsample<3>(bottom_up, w, h, pixels);
  } else {
    ECPSIM_DEMAND(supersample == 4);
    Downsample<4>(bottom_up, w, h, pixels);
  }
}

Image EmptyImage(int width, int height, ChannelOrder order) {
  Image image;
  image.width = width;
  image.height = height;
  image.order = order;
  image.pixels.resize(static_cast<size_t>(width) * height * 3);
  return image;
}

}  // namespace

Image Downsample(const Drawing& drawing) {
  ECPSIM_DEMAND(drawing.rgba != nullptr);
  ECPSIM_DEMAND(drawing.drawing_width == DrawingSize(drawing.width, drawing.supersample) &&
                drawing.drawing_height == DrawingSize(drawing.height, drawing.supersample));
  Image image = EmptyImage(drawing.width, drawing.height, drawing.order);
  DownsampleBy(drawing.supersample, drawing.rgba.get(), drawing.drawing_width,
               drawing.drawing_height, drawing.width, drawing.height, image.pixels.data());
  return image;
}

RenderTarget::RenderTarget(int width, int height, int samples, double supersample,
                           ChannelOrder order)
    : width_(width),
      height_(height),
      samples_(samples),
      supersample_(supersample),
      order_(order),
      draw_width_(DrawingSize(width, supersample)),
      draw_height_(DrawingSize(height, supersample)) {
  GLint max_size = 0, max_samples = 0;
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
  glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
  if (!IsSupportedFactor(supersample)) {
    throw std::runtime_error(
        fmt::format("supersampling {}x: expected 1, 1.5, 2, 3 or 4", supersample));
  }
  if (width < 1 || height < 1 || draw_width_ > max_size || draw_height_ > max_size) {
    throw std::runtime_error(fmt::format(
        "image size {}x{} with {}x supersampling is not supported: expected 1..{} drawing "
        "pixels per side",
        width, height, supersample, max_size));
  }
  // from here on the buffers have the drawing size
  width = draw_width_;
  height = draw_height_;
  if (samples < 1 || samples > max_samples) {
    throw std::runtime_error(fmt::format("{} samples per pixel are not supported: expected 1..{}",
                                         samples, max_samples));
  }

  // the multisampled buffer every frame is drawn into
  glGenFramebuffers(1, &draw_fbo_);
  glBindFramebuffer(GL_FRAMEBUFFER, draw_fbo_);
  glGenRenderbuffers(1, &draw_color_);
  glBindRenderbuffer(GL_RENDERBUFFER, draw_color_);
  // samples = 1 must be a plain buffer: a one-sample multisampled one cannot be read back
  if (samples > 1) {
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, width, height);
  } else {
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
  }
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, draw_color_);
  glGenRenderbuffers(1, &draw_depth_);
  glBindRenderbuffer(GL_RENDERBUFFER, draw_depth_);
  if (samples > 1) {
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH24_STENCIL8, width, height);
  } else {
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, width, height);
  }
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER,
                            draw_depth_);
  CheckComplete("multisampled", width, height, samples);

  // the single-sample buffer the samples are averaged into before reading
  glGenFramebuffers(1, &resolve_fbo_);
  glBindFramebuffer(GL_FRAMEBUFFER, resolve_fbo_);
  glGenRenderbuffers(1, &resolve_color_);
  glBindRenderbuffer(GL_RENDERBUFFER, resolve_color_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, resolve_color_);
  CheckComplete("resolve", width, height, 1);
  Bind();
}

RenderTarget::~RenderTarget() {
  glDeleteFramebuffers(1, &resolve_fbo_);
  glDeleteRenderbuffers(1, &resolve_color_);
  glDeleteFramebuffers(1, &draw_fbo_);
  glDeleteRenderbuffers(1, &draw_color_);
  glDeleteRenderbuffers(1, &draw_depth_);
}

void RenderTarget::Bind() const {
  glBindFramebuffer(GL_FRAMEBUFFER, draw_fbo_);
  glViewport(0, 0, width(), height());
}

void RenderTarget::Clear(const std::array<float, 4>& rgba) const {
  Bind();
  glDisable(GL_SCISSOR_TEST);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDepthMask(GL_TRUE);
  glStencilMask(0xff);
  glClearColor(rgba[0], rgba[1], rgba[2], rgba[3]);
  glClearDepth(1.0);
  glClearStencil(0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
}

void RenderTarget::ClearRect(int x, int y, int w, int h, const std::array<float, 4>& rgba) const {
  Bind();
  // OpenGL counts rows from the bottom: the image's row y is GL row height − 1 − y
  glEnable(GL_SCISSOR_TEST);
  glScissor(x, height() - y - h, w, h);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDepthMask(GL_TRUE);
  glStencilMask(0xff);
  glClearColor(rgba[0], rgba[1], rgba[2], rgba[3]);
  glClearDepth(1.0);
  glClearStencil(0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
  glDisable(GL_SCISSOR_TEST);
}

// resolves the samples and reads the drawing (bottom row first) into `rgba`
void RenderTarget::ReadInto(std::uint8_t* rgba) const {
  const int W = width(), H = height();
  // resolve the samples; a single-sample buffer is read directly
  if (samples_ > 1) {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, draw_fbo_);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolve_fbo_);
    glBlitFramebuffer(0, 0, W, H, 0, 0, W, H, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, resolve_fbo_);
  } else {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, draw_fbo_);
  }
  // RGBA matches the buffer's format, so Mesa copies it without a per-pixel conversion path
  // (measured 0.5 ms against 3.6 ms for GL_RGB at 1280×720); BGRA swaps red and blue on the way
  // (0.83 against 0.65 ms for 1920×1080 drawing pixels), and the downsample keeps the order of
  // the bytes it is given
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, W, H, order_ == ChannelOrder::kBgr ? GL_BGRA : GL_RGBA, GL_UNSIGNED_BYTE,
               rgba);
  Bind();
}

Image RenderTarget::Read() const {
  readback_.resize(static_cast<size_t>(width()) * height() * 4);
  ReadInto(readback_.data());
  Image image = EmptyImage(width_, height_, order_);
  DownsampleBy(supersample_, readback_.data(), width(), height(), width_, height_,
               image.pixels.data());
  return image;
}

Drawing RenderTarget::ReadDrawing(Drawing spare) const {
  Drawing drawing;
  if (spare.drawing_width == width() && spare.drawing_height == height()) {
    drawing.rgba = std::move(spare.rgba);
  }
  drawing.width = width_;
  drawing.height = height_;
  drawing.drawing_width = width();
  drawing.drawing_height = height();
  drawing.supersample = supersample_;
  drawing.order = order_;
  if (!drawing.rgba) {
    drawing.rgba.reset(new std::uint8_t[static_cast<size_t>(width()) * height() * 4]);
  }
  ReadInto(drawing.rgba.get());
  return drawing;
}

}  // namespace ecpsim::render
