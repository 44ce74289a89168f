#include "learn/graph_ops.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace wheelpose::learn::ops {
using torch::Tensor;

namespace {

std::string shape_text(c10::IntArrayRef shape) {
  std::string s = "[";
  for (std::size_t k = 0; k < shape.size(); ++k) s += (k ? "," : "") + std::to_string(shape[k]);
  return s + "]";
}

// An NHWC tensor as an NCHW view: channels-last memory (free for an NHWC-contiguous tensor) or
// NCHW-contiguous.
Tensor to_nchw(const Tensor& x, bool channels_last) {
  const Tensor v = x.permute({0, 3, 1, 2});
  return channels_last ? v.contiguous(at::MemoryFormat::ChannelsLast) : v.contiguous();
}

// Zero- (or `value`-) pads H and W of an NHWC tensor and returns the NCHW view. Channels-last
// pads in NHWC, where the copy is contiguous rows (constant_pad_nd of a channels-last NCHW
// tensor would produce NCHW-contiguous memory through a slow transposing copy).
Tensor pad_hw_nchw(const Tensor& x, std::int64_t top, std::int64_t bottom, std::int64_t left,
                   std::int64_t right, double value, bool channels_last) {
  if (channels_last) {
    return to_nchw(torch::constant_pad_nd(x.contiguous(), {0, 0, left, right, top, bottom}, value),
                   true);
  }
  return torch::constant_pad_nd(to_nchw(x, false), {left, right, top, bottom}, value);
}

bool use_mkldnn(const Tensor& in) {
  static const bool available = at::hasMKLDNN();
  return available && in.device().is_cpu() && in.scalar_type() == torch::kFloat;
}

// {top, bottom, left, right}.
std::array<std::int64_t, 4> pads_for(const Padding& p, std::int64_t in_h, std::int64_t in_w,
                                     std::int64_t kh, std::int64_t kw,
                                     std::array<std::int64_t, 2> stride,
                                     std::array<std::int64_t, 2> dilation) {
  switch (p.kind) {
    case Padding::Kind::kValid:
      return {0, 0, 0, 0};
    case Padding::Kind::kExplicit:
      return {p.top, p.bottom, p.left, p.right};
    case Padding::Kind::kSame: {
      const auto [t, b] = same_padding(in_h, kh, stride[0], dilation[0]);
      const auto [l, r] = same_padding(in_w, kw, stride[1], dilation[1]);
      return {t, b, l, r};
    }
  }
  return {0, 0, 0, 0};
}

void require_nhwc(const Tensor& x, const char* what) {
  if (x.dim() != 4) {
    throw OpError(std::string(what) + " input must be 4-D NHWC, is " + shape_text(x.sizes()));
  }
}

Tensor activate(const Tensor& y, const ConvSpec& spec, const Tensor& prelu_alpha) {
  const bool in_place = !torch::GradMode::is_enabled();
  switch (spec.activation) {
    case Activation::kNone:
      return y;
    case Activation::kRelu:
      return in_place ? y.relu_() : y.relu();
    case Activation::kRelu6:
      return in_place ? y.clamp_(0, 6) : y.clamp(0, 6);
    case Activation::kElu:
      return torch::elu(y);
    case Activation::kLeakyRelu:
      return torch::leaky_relu(y, spec.alpha);
    case Activation::kSigmoid:
      return y.sigmoid();
    case Activation::kTanh:
      return y.tanh();
    case Activation::kPrelu:
      return torch::where(y > 0, y, y * prelu_alpha);
  }
  return y;
}

struct AxisWeights {
  Tensor lower, upper, lerp;
};

// TF's compute_interpolation_weights (resize_bilinear_op.cc), float arithmetic as TF does it.
AxisWeights axis_weights(std::int64_t in, std::int64_t out, bool align_corners,
                         bool half_pixel_centers) {
  const float scale = (align_corners && out > 1)
                          ? static_cast<float>(in - 1) / static_cast<float>(out - 1)
                          : static_cast<float>(in) / static_cast<float>(out);
  std::vector<std::int64_t> lower(out), upper(out);
  std::vector<float> lerp(out);
  for (std::int64_t i = 0; i < out; ++i) {
    const float src = half_pixel_centers ? (static_cast<float>(i) + 0.5f) * scale - 0.5f
                                         : static_cast<float>(i) * scale;
    const float floor_src = std::floor(src);
    lower[i] = std::max<std::int64_t>(static_cast<std::int64_t>(floor_src), 0);
    upper[i] = std::min<std::int64_t>(static_cast<std::int64_t>(std::ceil(src)), in - 1);
    lerp[i] = src - floor_src;
  }
  return {torch::tensor(lower, torch::kLong), torch::tensor(upper, torch::kLong),
          torch::tensor(lerp, torch::kFloat)};
}

}  // namespace

std::pair<std::int64_t, std::int64_t> same_padding(std::int64_t in, std::int64_t kernel,
                                                   std::int64_t stride, std::int64_t dilation) {
  const std::int64_t effective = (kernel - 1) * dilation + 1;
  const std::int64_t out = (in + stride - 1) / stride;
  const std::int64_t total = std::max<std::int64_t>((out - 1) * stride + effective - in, 0);
  return {total / 2, total - total / 2};
}

Tensor depthwise_filter_to_torch(const Tensor& filter) {
  if (filter.dim() != 4) {
    throw OpError("depthwise filter must be [kh, kw, in, mult], is " + shape_text(filter.sizes()));
  }
  const std::int64_t kh = filter.size(0), kw = filter.size(1);
  return filter.reshape({kh, kw, filter.size(2) * filter.size(3)}).permute({2, 0, 1}).unsqueeze(1);
}

Tensor conv2d_nhwc(const Tensor& x, const Tensor& filter, const Tensor& bias,
                   const Tensor& prelu_alpha, const ConvSpec& spec, bool channels_last) {
  require_nhwc(x, "convolution");
  Tensor w = filter;
  if (!spec.filter_in_torch_layout) {
    if (filter.dim() != 4) throw OpError("filter must be 4-D, is " + shape_text(filter.sizes()));
    w = (spec.depthwise ? depthwise_filter_to_torch(filter) : filter.permute({3, 2, 0, 1}))
            .contiguous();
  }
  const Tensor xf = x.is_floating_point() ? x : x.to(torch::kFloat);
  const std::int64_t groups = spec.depthwise ? xf.size(3) : 1;
  if (spec.depthwise && w.size(0) % groups != 0) {
    throw OpError("depthwise filter " + shape_text(w.sizes()) + " does not fit " +
                  std::to_string(groups) + " input channels");
  }
  const auto [top, bottom, left, right] = pads_for(spec.padding, xf.size(1), xf.size(2), w.size(2),
                                                   w.size(3), spec.stride, spec.dilation);
  const bool symmetric = top == bottom && left == right;
  const Tensor in = symmetric ? to_nchw(xf, channels_last)
                              : pad_hw_nchw(xf, top, bottom, left, right, 0, channels_last);
  const std::vector<std::int64_t> padding =
      symmetric ? std::vector<std::int64_t>{top, left} : std::vector<std::int64_t>{0, 0};
  const std::vector<std::int64_t> stride = {spec.stride[0], spec.stride[1]};
  const std::vector<std::int64_t> dilation = {spec.dilation[0], spec.dilation[1]};
  Tensor y;
  if (use_mkldnn(in)) {
    // ATen would send small convolutions (batch 1, <= 20480 input values) to its im2col + BLAS
    // path; with Debian's reference BLAS that is several times slower than oneDNN.
    y = at::mkldnn_convolution(in, w, bias, padding, stride, dilation, groups);
  } else {
    y = torch::conv2d(in, w, bias, stride, padding, dilation, groups);
  }
  return activate(y.permute({0, 2, 3, 1}), spec, prelu_alpha);
}

Tensor max_pool_nhwc(const Tensor& x, std::array<std::int64_t, 2> ksize,
                     std::array<std::int64_t, 2> stride, const Padding& padding,
                     bool channels_last) {
  require_nhwc(x, "MaxPool");
  const auto [top, bottom, left, right] =
      pads_for(padding, x.size(1), x.size(2), ksize[0], ksize[1], stride, {1, 1});
  const std::vector<std::int64_t> k = {ksize[0], ksize[1]};
  const std::vector<std::int64_t> s = {stride[0], stride[1]};
  Tensor y;
  if (top == bottom && left == right && 2 * top <= ksize[0] && 2 * left <= ksize[1]) {
    // torch pads with -inf
    y = torch::max_pool2d(to_nchw(x, channels_last), k, s, std::vector<std::int64_t>{top, left});
  } else {
    const Tensor in = pad_hw_nchw(x, top, bottom, left, right,
                                  -std::numeric_limits<double>::infinity(), channels_last);
    y = torch::max_pool2d(in, k, s, std::vector<std::int64_t>{0, 0});
  }
  return y.permute({0, 2, 3, 1});
}

Tensor resize_bilinear(const Tensor& x, std::int64_t out_h, std::int64_t out_w, bool align_corners,
                       bool half_pixel_centers) {
  require_nhwc(x, "ResizeBilinear");
  if (!align_corners && !half_pixel_centers) {
    return resize_bilinear_reference(x, out_h, out_w, false, false);
  }
  // torch's align_corners=false is TF's half_pixel_centers (source index clamped at 0, upper
  // neighbour clamped at in-1, which equals TF's floor/ceil clamping); align_corners=true is
  // TF's align_corners.
  const Tensor in = (x.is_floating_point() ? x : x.to(torch::kFloat)).permute({0, 3, 1, 2});
  return torch::upsample_bilinear2d(in, {out_h, out_w}, align_corners).permute({0, 2, 3, 1});
}

Tensor resize_bilinear_reference(const Tensor& x, std::int64_t out_h, std::int64_t out_w,
                                 bool align_corners, bool half_pixel_centers) {
  require_nhwc(x, "ResizeBilinear");
  const Tensor xf = x.is_floating_point() ? x : x.to(torch::kFloat);
  const AxisWeights ys = axis_weights(xf.size(1), out_h, align_corners, half_pixel_centers);
  const AxisWeights xs = axis_weights(xf.size(2), out_w, align_corners, half_pixel_centers);
  const Tensor x_lerp = xs.lerp.view({1, 1, out_w, 1});
  auto horizontal = [&](const Tensor& rows) {
    const Tensor l = rows.index_select(2, xs.lower);
    const Tensor r = rows.index_select(2, xs.upper);
    return l + (r - l) * x_lerp;
  };
  const Tensor top = horizontal(xf.index_select(1, ys.lower));
  const Tensor bottom = horizontal(xf.index_select(1, ys.upper));
  return top + (bottom - top) * ys.lerp.view({1, out_h, 1, 1});
}

Tensor cast(const Tensor& x, torch::ScalarType dtype) {
  if (dtype == torch::kBool) return x.ne(0);
  return x.to(dtype);  // float -> int truncates toward zero, as TF's Cast
}

Tensor floor_div(const Tensor& x, const Tensor& y) {
  if (x.is_floating_point() || y.is_floating_point()) return torch::floor(x / y);
  return torch::div(x, y, "floor");
}

Tensor select_v1(const Tensor& cond, const Tensor& t, const Tensor& e) {
  if (cond.dim() == 0 || cond.dim() == t.dim()) return torch::where(cond, t, e);
  if (cond.dim() == 1 && t.dim() >= 1 && cond.size(0) == t.size(0)) {
    std::vector<std::int64_t> shape(t.dim(), 1);
    shape[0] = cond.size(0);
    return torch::where(cond.view(shape), t, e);
  }
  throw OpError("condition " + shape_text(cond.sizes()) + " does not fit " + shape_text(t.sizes()));
}

Tensor reduce(const Tensor& x, std::vector<std::int64_t> axes, Reduction r, bool keep_dims) {
  const std::int64_t rank = x.dim();
  for (std::int64_t& a : axes) {
    if (a < -rank || a >= std::max<std::int64_t>(rank, 1)) {
      throw OpError("reduction axis " + std::to_string(a) + " out of range for rank " +
                    std::to_string(rank));
    }
    if (a < 0) a += rank;
  }
  std::sort(axes.begin(), axes.end());
  axes.erase(std::unique(axes.begin(), axes.end()), axes.end());
  if (axes.empty() || rank == 0) return x;
  const bool integral = !x.is_floating_point();
  switch (r) {
    case Reduction::kSum:
      return integral ? x.sum(axes, keep_dims).to(x.scalar_type()) : x.sum(axes, keep_dims);
    case Reduction::kMax:
      return x.amax(axes, keep_dims);
    case Reduction::kMin:
      return x.amin(axes, keep_dims);
    case Reduction::kMean: {
      if (!integral) return x.mean(axes, keep_dims);
      std::int64_t count = 1;
      for (std::int64_t a : axes) count *= x.size(a);
      return torch::div(x.sum(axes, keep_dims), count, "trunc").to(x.scalar_type());
    }
  }
  return x;
}

Tensor arg_max(const Tensor& x, std::int64_t dim) {
  const std::int64_t rank = x.dim();
  if (dim < -rank || dim >= rank)
    throw OpError("dimension " + std::to_string(dim) + " out of range");
  if (dim < 0) dim += rank;
  return x.argmax(dim);  // the first maximum, as TF
}

std::pair<Tensor, Tensor> top_k(const Tensor& x, std::int64_t k) {
  if (x.dim() < 1) throw OpError("input must have rank >= 1");
  const std::int64_t n = x.size(-1);
  if (k < 0 || k > n) {
    throw OpError("k = " + std::to_string(k) + " but the last dimension has " + std::to_string(n));
  }
  // A stable descending sort keeps equal values in index order, as TF's TopKV2 returns them.
  auto [values, indices] = torch::sort(x, /*stable=*/true, /*dim=*/-1, /*descending=*/true);
  return {values.narrow(-1, 0, k), indices.narrow(-1, 0, k).to(torch::kInt)};
}

Tensor gather_nd(const Tensor& params, const Tensor& indices) {
  if (indices.dim() < 1) throw OpError("indices must have rank >= 1");
  const std::int64_t m = indices.size(-1);
  if (m > params.dim()) {
    throw OpError("indices " + shape_text(indices.sizes()) + " index more dimensions than params " +
                  shape_text(params.sizes()));
  }
  const Tensor idx = indices.to(torch::kLong).reshape({-1, m});
  Tensor linear = torch::zeros({idx.size(0)}, torch::kLong);
  for (std::int64_t j = 0; j < m; ++j) {
    const Tensor column = idx.select(1, j);
    if (idx.size(0) > 0 &&
        (column.lt(0).any().item<bool>() || column.ge(params.size(j)).any().item<bool>())) {
      throw OpError("an index in column " + std::to_string(j) + " is outside params " +
                    shape_text(params.sizes()));
    }
    linear = linear * params.size(j) + column;
  }
  const Tensor flat = m > 0 ? params.flatten(0, m - 1) : params.unsqueeze(0);
  std::vector<std::int64_t> shape(indices.sizes().begin(), indices.sizes().end() - 1);
  for (std::int64_t d = m; d < params.dim(); ++d) shape.push_back(params.size(d));
  return flat.index_select(0, linear).reshape(shape);
}

Tensor squeeze_dims(const Tensor& x, const std::vector<std::int64_t>& dims) {
  const std::int64_t rank = x.dim();
  std::vector<bool> drop(rank, false);
  if (dims.empty()) {
    for (std::int64_t d = 0; d < rank; ++d) drop[d] = x.size(d) == 1;
  } else {
    for (std::int64_t d : dims) {
      if (d < -rank || d >= rank)
        throw OpError("squeeze dim " + std::to_string(d) + " out of range");
      if (d < 0) d += rank;
      if (x.size(d) != 1) {
        throw OpError("cannot squeeze dim " + std::to_string(d) + " of " + shape_text(x.sizes()));
      }
      drop[d] = true;
    }
  }
  std::vector<std::int64_t> shape;
  for (std::int64_t d = 0; d < rank; ++d) {
    if (!drop[d]) shape.push_back(x.size(d));
  }
  return x.reshape(shape);
}

Tensor strided_slice(const Tensor& x, const std::vector<std::int64_t>& begin_in,
                     const std::vector<std::int64_t>& end_in,
                     const std::vector<std::int64_t>& strides_in, const SliceMasks& masks) {
  if (begin_in.size() != end_in.size() || begin_in.size() != strides_in.size()) {
    throw OpError("begin, end and strides must have equal lengths");
  }
  if (begin_in.size() > 32) throw OpError("too many slice dimensions");
  // The sparse spec; without an ellipsis TF appends one.
  std::vector<std::int64_t> begin = begin_in, end = end_in, strides = strides_in;
  std::int64_t ellipsis = masks.ellipsis;
  int sparse_dims = static_cast<int>(begin.size());
  if ((ellipsis & (ellipsis - 1)) != 0) throw OpError("more than one ellipsis");
  if (ellipsis == 0) {
    ellipsis |= std::int64_t{1} << sparse_dims;
    begin.push_back(0);
    end.push_back(0);
    strides.push_back(1);
    ++sparse_dims;
  }
  int new_axes_after_ellipsis = 0;
  bool after = false;
  for (int i = 0; i < sparse_dims; ++i) {
    if (after && ((masks.new_axis >> i) & 1)) ++new_axes_after_ellipsis;
    if ((ellipsis >> i) & 1) after = true;
  }

  // The dense spec over x's dimensions.
  constexpr std::int64_t kNewAxis = -1, kShrinkAxis = -2;
  const int dims = static_cast<int>(x.dim());
  std::vector<std::int64_t> d_begin(dims, 0), d_end(dims, 0), d_stride(dims, 1);
  std::vector<bool> d_begin_mask(dims, false), d_end_mask(dims, false), d_shrink(dims, false);
  std::vector<std::int64_t> final_gather;
  int full = 0;
  for (int i = 0; i < sparse_dims; ++i) {
    if ((ellipsis >> i) & 1) {
      const int next = std::min(dims - (sparse_dims - i) + 1 + new_axes_after_ellipsis, dims);
      for (; full < next; ++full) {
        d_begin_mask[full] = d_end_mask[full] = true;
        final_gather.push_back(full);
      }
    } else if ((masks.new_axis >> i) & 1) {
      final_gather.push_back(kNewAxis);
    } else {
      if (full >= dims) {
        throw OpError("slice index " + std::to_string(i) + " out of range for rank " +
                      std::to_string(dims));
      }
      d_begin[full] = begin[i];
      d_end[full] = end[i];
      d_stride[full] = strides[i];
      d_begin_mask[full] = (masks.begin >> i) & 1;
      d_end_mask[full] = (masks.end >> i) & 1;
      if ((masks.shrink_axis >> i) & 1) {
        d_shrink[full] = true;
        final_gather.push_back(kShrinkAxis);
      } else {
        final_gather.push_back(full);
      }
      ++full;
    }
  }

  Tensor t = x;
  for (int d = 0; d < dims; ++d) {
    const std::int64_t dim = x.size(d);
    const std::int64_t stride = d_stride[d];
    if (stride == 0) throw OpError("stride 0 in dimension " + std::to_string(d));
    std::int64_t start, size;
    if (d_shrink[d]) {
      if (stride <= 0) throw OpError("only stride 1 allowed on a shrunk dimension");
      start = d_begin[d] < 0 ? dim + d_begin[d] : d_begin[d];
      if (start < 0 || start >= dim) {
        throw OpError("slice index " + std::to_string(d_begin[d]) + " of dimension " +
                      std::to_string(d) + " out of bounds");
      }
      size = 1;
    } else {
      const std::int64_t lo = stride > 0 ? 0 : -1;
      const std::int64_t hi = stride > 0 ? dim : dim - 1;
      auto canonical = [&](std::int64_t v, bool masked, bool is_begin) {
        if (masked) return (stride > 0) == is_begin ? lo : hi;
        const std::int64_t fwd = v < 0 ? dim + v : v;
        return std::clamp(fwd, lo, hi);
      };
      start = canonical(d_begin[d], d_begin_mask[d], true);
      const std::int64_t stop = canonical(d_end[d], d_end_mask[d], false);
      const std::int64_t interval = stop - start;
      size = (interval == 0 || (interval < 0) != (stride < 0))
                 ? 0
                 : interval / stride + (interval % stride != 0 ? 1 : 0);
    }
    if (size == 0) {
      t = t.narrow(d, 0, 0);
    } else if (stride > 0 || d_shrink[d]) {
      const std::int64_t step = d_shrink[d] ? 1 : stride;
      t = t.slice(d, start, start + (size - 1) * step + 1, step);
    } else {
      t = t.index_select(d, torch::arange(start, start + size * stride, stride, torch::kLong));
    }
  }
  std::vector<std::int64_t> shape;
  for (std::int64_t g : final_gather) {
    if (g == kShrinkAxis) continue;
    shape.push_back(g == kNewAxis ? 1 : t.size(g));
  }
  return t.reshape(shape);
}

Tensor range(const Tensor& start, const Tensor& limit, const Tensor& delta) {
  if (start.numel() != 1 || limit.numel() != 1 || delta.numel() != 1) {
    throw OpError("start, limit and delta must be scalars");
  }
  if (start.is_floating_point()) {
    const float s = start.item<float>(), l = limit.item<float>(), d = delta.item<float>();
    if (d == 0) throw OpError("delta must not be 0");
    if ((d > 0 && s > l) || (d < 0 && s < l)) {
      throw OpError("start " + std::to_string(s) + " and limit " + std::to_string(l) +
                    " do not fit delta " + std::to_string(d));
    }
    const auto size = static_cast<std::int64_t>(std::ceil(std::abs((l - s) / d)));
    std::vector<float> values(size);
    float v = s;
    for (std::int64_t i = 0; i < size; ++i, v += d) values[i] = v;
    return torch::tensor(values, torch::kFloat).to(start.scalar_type());
  }
  const std::int64_t s = int_value(start), l = int_value(limit), d = int_value(delta);
  if (d == 0) throw OpError("delta must not be 0");
  if ((d > 0 && s > l) || (d < 0 && s < l)) {
    throw OpError("start " + std::to_string(s) + " and limit " + std::to_string(l) +
                  " do not fit delta " + std::to_string(d));
  }
  const std::int64_t size = (std::abs(l - s) + std::abs(d) - 1) / std::abs(d);
  return torch::arange(s, s + size * d, d, torch::kLong).to(start.scalar_type());
}

std::vector<std::int64_t> int_values(const Tensor& t) {
  if (t.is_floating_point()) throw OpError("expected an integer tensor");
  const Tensor c = t.detach().to(torch::kLong).contiguous();
  const std::int64_t* p = c.data_ptr<std::int64_t>();
  return std::vector<std::int64_t>(p, p + c.numel());
}

std::int64_t int_value(const Tensor& t) {
  if (t.numel() != 1) throw OpError("expected a scalar, got " + shape_text(t.sizes()));
  return int_values(t)[0];
}

}  // namespace wheelpose::learn::ops
