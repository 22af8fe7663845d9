#include "renderer/image/exr_file.h"
#include "geometry/errors.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfThreading.h>

#include <Imath/half.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <thread>
#include <type_traits>

#include "renderer/image/film.h"

namespace isotrace {

namespace {

// OpenEXR compresses and decompresses blocks in parallel on its own pool,
// sized once for the machine.
void useAllCores() {
    static const bool once = [] {
        Imf::setGlobalThreadCount(int(std::max(1u, std::thread::hardware_concurrency())));
        return true;
    }();
    (void)once;
}

// Where a channel goes when read back: colour first, then the AOV channels
// in the order renders write them, then any others by name.
size_t channelRank(const std::string& name) {
    static const std::vector<std::string> order = [] {
        std::vector<std::string> names = {"R", "G", "B", "A", "Y"};
        const AovLayout every(AovLayout::names());
        names.insert(names.end(), every.channels().begin(), every.channels().end());
        return names;
    }();
    const auto it = std::find(order.begin(), order.end(), name);
    return it == order.end() ? order.size() : size_t(it - order.begin());
}

// Files larger than this (in float samples, 8 GB) are refused before
// anything is allocated: a corrupt header can claim any size.
constexpr double kMaximumSamples = double(1u << 31);

// A slice addresses pixel (x, y) of the data window `window` at
// base + x dx + y dy, where `first` is the window's first sample.
template <typename Sample>
Imf::Slice sliceOf(const Sample* first, size_t stride, const Imath::Box2i& window) {
    const size_t dx = stride * sizeof(Sample), dy = dx * size_t(window.max.x - window.min.x + 1);
    char* base = reinterpret_cast<char*>(const_cast<Sample*>(first)) - ptrdiff_t(window.min.x) * ptrdiff_t(dx) -
                 ptrdiff_t(window.min.y) * ptrdiff_t(dy);
    return Imf::Slice(std::is_same_v<Sample, half> ? Imf::HALF : Imf::FLOAT, base, dx, dy);
}

// The image's window in its frame, as inclusive corners.
Imath::Box2i dataWindowOf(const ImageFile& image) {
    return Imath::Box2i(Imath::V2i(image.x, image.y), Imath::V2i(image.x + image.width - 1, image.y + image.height - 1));
}

// The window inside its frame, ZIP compression, the string attributes and
// every channel as float or half.
Imf::Header headerFor(const ImageFile& image, SampleFormat format) {
    const int fullWidth = image.fullWidth > 0 ? image.fullWidth : image.width;
    const int fullHeight = image.fullHeight > 0 ? image.fullHeight : image.height;
    const Imath::Box2i display(Imath::V2i(0, 0), Imath::V2i(fullWidth - 1, fullHeight - 1));
    Imf::Header header(display, dataWindowOf(image));
    header.compression() = Imf::ZIP_COMPRESSION;
    // zlib's fastest level: on rendered float images it writes files 2%
    // larger than the default level 4 in two thirds of the time (640x480
    // RGB: 9 ms against 13-15 ms, a tenth of a small render's process).
    header.zipCompressionLevel() = 1;
    for (const auto& [name, value] : image.strings) header.insert(name, Imf::StringAttribute(value));
    for (const std::string& name : image.channelNames)
        header.channels().insert(name, Imf::Channel(format == SampleFormat::Half ? Imf::HALF : Imf::FLOAT));
    return header;
}

// Where the value of string attribute `name` starts in a file's first bytes,
// or npos. The header follows the 4-byte magic number and 4-byte version:
// attributes are a name, a type (both NUL-terminated), a 4-byte
// little-endian size and the value; an empty name ends them.
size_t stringValueOffset(const std::string& head, const std::string& name) {
    size_t at = 8;
    while (at < head.size()) {
        const size_t nameEnd = head.find('\0', at);
        if (nameEnd == std::string::npos || nameEnd == at) return std::string::npos;
        const size_t typeEnd = head.find('\0', nameEnd + 1);
        if (typeEnd == std::string::npos || typeEnd + 5 > head.size()) return std::string::npos;
        uint32_t size = 0;
        for (int b = 3; b >= 0; --b) size = (size << 8) | uint8_t(head[typeEnd + 1 + size_t(b)]);
        const size_t value = typeEnd + 5;
        if (head.compare(at, nameEnd - at, name) == 0 && head.compare(nameEnd + 1, typeEnd - nameEnd - 1, "string") == 0)
            return value;
        at = value + size;
    }
    return std::string::npos;
}

}  // namespace

void writeExr(const std::string& path, const ImageFile& image, SampleFormat format) {
    if (image.pixels.size() != size_t(image.width) * image.height * image.channelNames.size())
        throw std::invalid_argument("writeExr: the pixels do not match the size and channels");
    writeExr(path, image, image.pixels.data(), format);
}

void writeExr(const std::string& path, const ImageFile& image, const float* pixels, SampleFormat format) {
    if (format == SampleFormat::Byte) throw std::invalid_argument("writeExr: EXR stores float or half samples");
    useAllCores();
    try {
        Imf::Header header = headerFor(image, format);
        // OpenEXR converts types when reading but not when writing: half
        // files are written from half samples.
        const bool toHalf = format == SampleFormat::Half;
        std::vector<half> halves(toHalf ? size_t(image.width) * image.height * image.channelNames.size() : 0);
        std::copy(pixels, pixels + halves.size(), halves.begin());
        Imf::FrameBuffer frame;
        const size_t channels = image.channelNames.size();
        const Imath::Box2i data = header.dataWindow();
        for (size_t c = 0; c < channels; ++c)
            frame.insert(image.channelNames[c], toHalf ? sliceOf(halves.data() + c, channels, data)
                                                       : sliceOf(pixels + c, channels, data));
        Imf::OutputFile file(path.c_str(), header);
        file.setFrameBuffer(frame);
        file.writePixels(image.height);
    } catch (const std::exception& e) {
        throw geometry::IoError(path, std::string("cannot write image: ") + e.what());
    }
}

// The file, written as OpenEXR asks; the first bytes (the header) are kept
// as well, so that finish() can find where a late value goes.
class ExrRowWriter::FileStream : public Imf::OStream {
public:
    explicit FileStream(const std::string& path) : Imf::OStream(path.c_str()), file_(path, std::ios::binary | std::ios::trunc) {
        if (!file_) throw std::runtime_error("cannot open for writing: " + std::string(std::strerror(errno)));
    }
    void write(const char c[], int n) override {
        if (position_ < kHeadBytes) {
            const size_t kept = std::min<size_t>(size_t(n), kHeadBytes - position_);
            if (head_.size() < position_ + kept) head_.resize(position_ + kept);
            head_.replace(position_, kept, c, kept);
        }
        file_.write(c, n);
        position_ += size_t(n);
        check();
    }
    uint64_t tellp() override { return position_; }
    void seekp(uint64_t position) override {
        file_.seekp(std::streamoff(position));
        position_ = size_t(position);
        check();
    }
    const std::string& head() const { return head_; }
    void close() {
        file_.close();
        check();
    }

private:
    // Far more than any header here: a few hundred bytes of attributes.
    static constexpr size_t kHeadBytes = 1 << 16;
    void check() {
        if (!file_) throw std::runtime_error(std::strerror(errno));
    }
    std::ofstream file_;
    std::string head_;
    size_t position_ = 0;
};

struct ExrRowWriter::Encoder {
    explicit Encoder(const std::string& path) : stream(path) {}
    FileStream stream;
    std::unique_ptr<Imf::OutputFile> file;
};

ExrRowWriter::ExrRowWriter(const std::string& path, const ImageFile& layout, SampleFormat format,
                           std::vector<std::pair<std::string, size_t>> lateStrings)
    : layout_(layout), format_(format), late_(std::move(lateStrings)) {
    if (format == SampleFormat::Byte) throw std::invalid_argument("ExrRowWriter: EXR stores float or half samples");
    layout_.pixels.clear();
    // Each late value is written as spaces now and overwritten in place by
    // finish(): the header precedes the pixels and its size cannot change.
    for (const auto& [name, width] : late_) layout_.strings.emplace_back(name, std::string(width, ' '));
    if (format == SampleFormat::Half) halves_.resize(size_t(layout_.width) * layout_.height * layout_.channelNames.size());
    try {
        encoder_ = std::make_unique<Encoder>(path);
        // No worker threads of OpenEXR's own: each band is compressed by
        // the thread that hands it over, while the others go on making rows.
        encoder_->file = std::make_unique<Imf::OutputFile>(encoder_->stream, headerFor(layout_, format), 0);
    } catch (const std::exception& e) {
        throw std::runtime_error(path + ": cannot write image: " + e.what());
    }
}
ExrRowWriter::~ExrRowWriter() = default;

void ExrRowWriter::writeRows(const std::vector<ChannelPlane>& planes, int end) {
    if (planes.size() != layout_.channelNames.size())
        throw std::invalid_argument("ExrRowWriter: one plane per channel is needed");
    if (end < rowsWritten_ || end > layout_.height) throw std::invalid_argument("ExrRowWriter: rows out of order");
    if (end == rowsWritten_) return;
    const Imath::Box2i data = dataWindowOf(layout_);
    const size_t channels = planes.size(), width = size_t(layout_.width);
    Imf::FrameBuffer frame;
    for (size_t c = 0; c < channels; ++c) {
        const ChannelPlane& plane = planes[c];
        if (format_ == SampleFormat::Half) {
            // Only the new rows are converted, into the file's channel-interleaved layout.
            for (size_t i = size_t(rowsWritten_) * width; i < size_t(end) * width; ++i)
                halves_[i * channels + c] = half(plane.first[i * plane.stride]).bits();
            frame.insert(layout_.channelNames[c], sliceOf(reinterpret_cast<const half*>(halves_.data()) + c, channels, data));
        } else {
            frame.insert(layout_.channelNames[c], sliceOf(plane.first, plane.stride, data));
        }
    }
    try {
        encoder_->file->setFrameBuffer(frame);
        encoder_->file->writePixels(end - rowsWritten_);
    } catch (const std::exception& e) {
        throw geometry::IoError(std::string("cannot write image: ") + e.what());
    }
    rowsWritten_ = end;
}

void ExrRowWriter::finish(const std::vector<std::pair<std::string, std::string>>& lateValues) {
    if (rowsWritten_ != layout_.height) throw std::logic_error("ExrRowWriter::finish: rows are missing");
    try {
        encoder_->file.reset();  // writes the table of row-band offsets
        FileStream& stream = encoder_->stream;
        for (const auto& [name, value] : lateValues) {
            const auto reserved =
                std::find_if(late_.begin(), late_.end(), [&name = name](const auto& l) { return l.first == name; });
            if (reserved == late_.end() || value.size() > reserved->second)
                throw std::logic_error("ExrRowWriter::finish: no room was reserved for \"" + name + "\" = \"" + value + "\"");
            const size_t at = stringValueOffset(stream.head(), name);
            if (at == std::string::npos) throw std::logic_error("ExrRowWriter::finish: \"" + name + "\" is not in the header");
            stream.seekp(at);
            stream.write(value.data(), int(value.size()));
        }
        stream.close();
    } catch (const std::logic_error&) {
        throw;
    } catch (const std::exception& e) {
        throw geometry::IoError(std::string("cannot write image: ") + e.what());
    }
}

ImageFile readExr(const std::string& path, bool withPixels) {
    useAllCores();
    try {
        Imf::InputFile file(path.c_str());
        const Imf::Header& header = file.header();
        const Imath::Box2i data = header.dataWindow(), display = header.displayWindow();
        // Windows are inclusive corners of any int values: sizes in 64 bits.
        auto span = [](int lo, int hi) { return (long long)hi - lo + 1; };
        const long long width = span(data.min.x, data.max.x), height = span(data.min.y, data.max.y);
        const long long fullWidth = span(display.min.x, display.max.x), fullHeight = span(display.min.y, display.max.y);
        if (width < 1 || height < 1 || fullWidth < 1 || fullHeight < 1 || width * height > (1ll << 31) ||
            fullWidth * fullHeight > (1ll << 31))
            throw std::runtime_error("the data or display window is empty or too large");
        ImageFile image;
        image.width = int(width);
        image.height = int(height);
        image.x = int((long long)data.min.x - display.min.x);
        image.y = int((long long)data.min.y - display.min.y);
        image.fullWidth = int(fullWidth);
        image.fullHeight = int(fullHeight);
        for (auto it = header.channels().begin(); it != header.channels().end(); ++it)
            image.channelNames.push_back(it.name());
        std::stable_sort(image.channelNames.begin(), image.channelNames.end(),
                         [](const std::string& a, const std::string& b) { return channelRank(a) < channelRank(b); });
        for (auto it = header.begin(); it != header.end(); ++it)
            if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&it.attribute()))
                image.strings.emplace_back(it.name(), s->value());
        if (image.channelNames.empty()) throw std::runtime_error("the file has no channels");
        const size_t channels = image.channelNames.size();
        if (double(image.width) * double(image.height) * double(channels) > kMaximumSamples)
            throw std::runtime_error("the image is too large (" + std::to_string(image.width) + "x" +
                                     std::to_string(image.height) + ", " + std::to_string(channels) + " channels)");
        if (!withPixels) return image;
        image.pixels.assign(size_t(image.width) * image.height * channels, 0.0f);
        Imf::FrameBuffer frame;
        for (size_t c = 0; c < channels; ++c)
            frame.insert(image.channelNames[c], sliceOf(image.pixels.data() + c, channels, data));
        file.setFrameBuffer(frame);
        file.readPixels(data.min.y, data.max.y);
        return image;
    } catch (const std::exception& e) {
        throw geometry::IoError(path, std::string("cannot read image: ") + e.what());
    }
}

}  // namespace isotrace
