// Image sizes against the frame limit: a camera checks an image fits one
// frame before it builds it, and refuses (never truncates) one that does
// not. Shared by every camera device (simulated or driver) and the client.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "wire/schemas/message_generated.h"

namespace troupe::wire {

/// Bytes per pixel of an uncompressed format (0 for an unknown one).
size_t bytes_per_pixel(PixelFormat format);

/// Bytes a frame carrying an uncompressed image of this size needs at most,
/// prefix included: the pixels plus the envelope (header, tables,
/// alignment), so that an image this says fits always does.
size_t image_frame_bytes(uint32_t width, uint32_t height, PixelFormat format);

/// Bytes the envelope of an image frame takes at most, prefix included.
inline constexpr size_t kImageEnvelopeBytes = 128;

/// True when such an image fits a frame of `max_frame_bytes` (prefix
/// included); otherwise false and `why` says how large it is against the
/// limit, naming the size and format.
bool image_fits(uint32_t width, uint32_t height, PixelFormat format, size_t max_frame_bytes, std::string& why);

/// True when an image holds every pixel it says it has: uncompressed, a
/// known format, a stride of at least a row and `height` rows of data (the
/// last row may end after its pixels); compressed, some data. Otherwise
/// false and `why` says what is missing. A frame that verifies can still
/// carry such an image (a damaged recording, a faulty driver); whoever
/// serves or reads pixels checks this first.
bool image_complete(const CameraImage& image, std::string& why);

}  // namespace troupe::wire
