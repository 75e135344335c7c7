#include "drivers/v4l2/capture.h"

#include <fcntl.h>
#include <linux/videodev2.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace troupe::drivers::v4l2 {
namespace {

uint32_t fourcc_code(Fourcc f) {
  switch (f) {
    case Fourcc::Rgb24:
      return V4L2_PIX_FMT_RGB24;
    case Fourcc::Yuyv:
      return V4L2_PIX_FMT_YUYV;
    case Fourcc::Grey:
      return V4L2_PIX_FMT_GREY;
  }
  return 0;
}

// An ioctl retried when a signal interrupted it.
int xioctl(int fd, unsigned long request, void* arg) {
  int r;
  do {
    r = ioctl(fd, request, arg);
  } while (r < 0 && errno == EINTR);
  return r;
}

}  // namespace

bool Capture::fail(const std::string& step, std::string& error) {
  const int err = errno;
  error = device_ + ": " + step + ": " + std::strerror(err);
  close();
  return false;
}

bool Capture::open(const CaptureRequest& want, std::string& error) {
  close();
  device_ = want.device;
  fd_ = ::open(want.device.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) return fail("open", error);

  v4l2_capability cap{};
  if (xioctl(fd_, VIDIOC_QUERYCAP, &cap) < 0) return fail("VIDIOC_QUERYCAP (not a V4L2 device?)", error);
  const uint32_t caps = (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
  if (!(caps & V4L2_CAP_VIDEO_CAPTURE) || !(caps & V4L2_CAP_STREAMING)) {
    error = device_ + ": not a single-planar video capture device with streaming I/O (" +
            reinterpret_cast<const char*>(cap.card) + ")";
    close();
    return false;
  }

  // The first acceptable format in the driver's order of preference that
  // the camera lists.
  bool listed[3] = {};
  v4l2_fmtdesc desc{};
  desc.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  for (desc.index = 0; xioctl(fd_, VIDIOC_ENUM_FMT, &desc) == 0; ++desc.index) {
    for (Fourcc f : {Fourcc::Rgb24, Fourcc::Yuyv, Fourcc::Grey}) {
      if (desc.pixelformat == fourcc_code(f)) listed[int(f)] = true;
    }
  }
  bool chosen = false;
  for (size_t i = 0; i < want.format_count && !chosen; ++i) {
    if (listed[int(want.formats[i])]) {
      format_ = want.formats[i];
      chosen = true;
    }
  }
  if (!chosen) {
    error = device_ + ": the camera offers none of the capture formats asked for (RGB24, YUYV, GREY)";
    close();
    return false;
  }

  v4l2_format fmt{};
  fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  fmt.fmt.pix.width = want.width;
  fmt.fmt.pix.height = want.height;
  fmt.fmt.pix.pixelformat = fourcc_code(format_);
  fmt.fmt.pix.field = V4L2_FIELD_NONE;
  if (xioctl(fd_, VIDIOC_S_FMT, &fmt) < 0) return fail("VIDIOC_S_FMT", error);
  if (fmt.fmt.pix.pixelformat != fourcc_code(format_) || fmt.fmt.pix.width == 0 || fmt.fmt.pix.height == 0 ||
      (format_ == Fourcc::Yuyv && fmt.fmt.pix.width % 2 != 0)) {
    error = device_ + ": the camera changed the format asked for into one the driver cannot read";
    close();
    return false;
  }
  width_ = fmt.fmt.pix.width;
  height_ = fmt.fmt.pix.height;
  stride_ = fmt.fmt.pix.bytesperline ? fmt.fmt.pix.bytesperline : width_ * capture_bytes_per_pixel(format_);
  if (stride_ < width_ * capture_bytes_per_pixel(format_)) {
    error = device_ + ": the camera's rows are shorter than its width";
    close();
    return false;
  }
  full_range_ = fmt.fmt.pix.quantization == V4L2_QUANTIZATION_FULL_RANGE;

  // The rate: a camera without frame interval control keeps its own.
  rate_ = 0;
  v4l2_streamparm parm{};
  parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (xioctl(fd_, VIDIOC_G_PARM, &parm) == 0 && (parm.parm.capture.capability & V4L2_CAP_TIMEPERFRAME) &&
      want.rate > 0) {
    parm.parm.capture.timeperframe.numerator = 1000;
    parm.parm.capture.timeperframe.denominator = uint32_t(want.rate * 1000.0f + 0.5f);
    xioctl(fd_, VIDIOC_S_PARM, &parm);  // refused: it keeps its rate, read back below
  }
  if (xioctl(fd_, VIDIOC_G_PARM, &parm) == 0 && parm.parm.capture.timeperframe.numerator != 0) {
    rate_ =
        float(parm.parm.capture.timeperframe.denominator) / float(parm.parm.capture.timeperframe.numerator);
  }

  v4l2_requestbuffers req{};
  req.count = want.buffers < 2 ? 2 : want.buffers > kMaxBuffers ? kMaxBuffers : want.buffers;
  req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  req.memory = V4L2_MEMORY_MMAP;
  if (xioctl(fd_, VIDIOC_REQBUFS, &req) < 0) return fail("VIDIOC_REQBUFS (memory-mapped streaming)", error);
  if (req.count < 2) {
    errno = ENOMEM;
    return fail("VIDIOC_REQBUFS gave fewer than 2 buffers", error);
  }
  buffer_count_ = req.count > kMaxBuffers ? kMaxBuffers : req.count;
  for (uint32_t i = 0; i < buffer_count_; ++i) {
    v4l2_buffer buf{};
    buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    buf.memory = V4L2_MEMORY_MMAP;
    buf.index = i;
    if (xioctl(fd_, VIDIOC_QUERYBUF, &buf) < 0) return fail("VIDIOC_QUERYBUF", error);
    void* p = mmap(nullptr, buf.length, PROT_READ | PROT_WRITE, MAP_SHARED, fd_, buf.m.offset);
    if (p == MAP_FAILED) return fail("mmap", error);
    buffers_[i] = {p, buf.length};
    if (xioctl(fd_, VIDIOC_QBUF, &buf) < 0) return fail("VIDIOC_QBUF", error);
  }
  v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (xioctl(fd_, VIDIOC_STREAMON, &type) < 0) return fail("VIDIOC_STREAMON", error);
  streaming_ = true;
  return true;
}

void Capture::close() {
  if (fd_ < 0) return;
  if (streaming_) {
    v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    xioctl(fd_, VIDIOC_STREAMOFF, &type);  // a vanished device refuses; closing frees it anyway
    streaming_ = false;
  }
  for (uint32_t i = 0; i < kMaxBuffers; ++i) {
    if (buffers_[i].start != nullptr) munmap(buffers_[i].start, buffers_[i].length);
    buffers_[i] = {};
  }
  buffer_count_ = 0;
  ::close(fd_);
  fd_ = -1;
}

Dequeued Capture::dequeue(Frame& frame, std::string& error) {
  v4l2_buffer buf{};
  buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  buf.memory = V4L2_MEMORY_MMAP;
  if (xioctl(fd_, VIDIOC_DQBUF, &buf) < 0) {
    if (errno == EAGAIN) return Dequeued::Nothing;
    error = device_ + ": VIDIOC_DQBUF: " + std::strerror(errno);
    return Dequeued::Lost;
  }
  if (buf.index >= buffer_count_) {
    error = device_ + ": the camera returned buffer " + std::to_string(buf.index) + " it was never given";
    return Dequeued::Lost;
  }
  frame.index = buf.index;
  frame.data = static_cast<const uint8_t*>(buffers_[buf.index].start);
  // A buffer flagged as corrupted, or shorter than an image, is handed
  // back unread (bytes 0).
  const size_t need = stride_ * (height_ - 1) + width_ * capture_bytes_per_pixel(format_);
  frame.bytes = (buf.flags & V4L2_BUF_FLAG_ERROR) || buf.bytesused < need ? 0 : buf.bytesused;
  frame.monotonic_us = (buf.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC
                           ? uint64_t(buf.timestamp.tv_sec) * 1000000u + uint64_t(buf.timestamp.tv_usec)
                           : 0;
  return Dequeued::Frame;
}

bool Capture::release(const Frame& frame, std::string& error) {
  v4l2_buffer buf{};
  buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  buf.memory = V4L2_MEMORY_MMAP;
  buf.index = frame.index;
  if (xioctl(fd_, VIDIOC_QBUF, &buf) < 0) {
    error = device_ + ": VIDIOC_QBUF: " + std::strerror(errno);
    return false;
  }
  return true;
}

}  // namespace troupe::drivers::v4l2
