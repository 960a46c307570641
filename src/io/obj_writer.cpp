// Writing a quad mesh as OBJ: records formatted into blocks (which a second thread writes out while
// the next is formatted, on large meshes) and written to a temporary file, which is renamed into
// place once complete (and removed on a problem), so no partial file is ever left at the path.
#include "qex/io.h"

#include "io/file_io.h"

#include <algorithm>
#include <charconv>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <new>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

namespace qex {
namespace {

/// Text formatted into a growing buffer. Numbers go through std::to_chars: the shortest text
/// that reads back to the same double, and plain decimals for integers.
class alignas(64) Text {
public:
    /// Room for `bytes` more characters.
    void reserve(std::size_t bytes) {
        const auto used = static_cast<std::size_t>(p_ - buf_.data());
        if (buf_.size() - used >= bytes) return;
        buf_.resize(std::max(2 * buf_.size(), used + bytes));
        p_ = buf_.data() + used;
    }
    void put(char c) { *p_++ = c; }
    void put(const char* text) {
        while (*text) *p_++ = *text++;
    }
    template <class T>
    void number(T x) {
        p_ = std::to_chars(p_, buf_.data() + buf_.size(), x).ptr;
    }
    const char* data() const { return buf_.data(); }
    std::size_t size() const { return static_cast<std::size_t>(p_ - buf_.data()); }
    void clear() { p_ = buf_.data(); }

private:
    std::vector<char> buf_;
    char* p_ = nullptr;
};

/// Meshes from this many faces on are written on two threads (about 9 MB of OBJ).
constexpr std::size_t kOverlapFaces = std::size_t{1} << 16;

/// The longest text of one number: a double's shortest form (24 characters) or a 64-bit integer.
constexpr std::size_t kNumber = 32;

/// Text formatted into blocks, written to a file in order. With `overlap`, a block is written
/// on a second thread while the next one is formatted (the two alternate between two buffers),
/// so the kernel's copy of the text costs no formatting time.
class BlockWriter {
public:
    BlockWriter(std::FILE* f, bool overlap) : f_(f) {
        if (overlap)
            for (Text& text : texts_) text.reserve(kBlock + 4096); // else grown as needed (small files)
        if (overlap) try {
                writer_ = std::thread([this] { write_loop(); });
            } catch (const std::system_error&) { // no thread to be had: written serially
            }
    }
    ~BlockWriter() { finish(); }

    /// The block being formatted; `ready()` after each record.
    Text& text() { return texts_[current_]; }

    /// Hands the block on once it holds kBlock characters.
    void ready() {
        if (texts_[current_].size() >= kBlock) hand_on();
    }

    /// Writes out what is left and waits for the writes to end.
    void finish() {
        hand_on();
        if (!writer_.joinable()) return;
        {
            const std::lock_guard<std::mutex> lock(mutex_);
            stop_ = true;
        }
        changed_.notify_all();
        writer_.join();
    }

private:
    static constexpr std::size_t kBlock = std::size_t{1} << 22;

    /// Writes the current block (on the writer thread, if any) and switches to the other buffer,
    /// once the writer is done with it.
    void hand_on() {
        if (!writer_.joinable()) {
            // After a write error (a full disk) nothing more is written: the caller reports it.
            if (!std::ferror(f_)) std::fwrite(texts_[current_].data(), 1, texts_[current_].size(), f_);
            texts_[current_].clear();
            return;
        }
        std::unique_lock<std::mutex> lock(mutex_);
        changed_.wait(lock, [this] { return pending_ < 0; });
        pending_ = current_;
        current_ = 1 - current_;
        texts_[current_].clear();
        lock.unlock();
        changed_.notify_all();
    }

    void write_loop() {
        std::unique_lock<std::mutex> lock(mutex_);
        for (;;) {
            changed_.wait(lock, [this] { return pending_ >= 0 || stop_; });
            if (pending_ < 0) return; // stopped with nothing left
            const Text& text = texts_[pending_];
            lock.unlock();
            if (!std::ferror(f_)) std::fwrite(text.data(), 1, text.size(), f_);
            lock.lock();
            pending_ = -1;
            changed_.notify_all();
        }
    }

    std::FILE* f_;
    Text texts_[2];
    int current_ = 0;
    int pending_ = -1; ///< the buffer the writer thread is to write, or -1
    bool stop_ = false;
    std::mutex mutex_;
    std::condition_variable changed_;
    std::thread writer_;
};

/// Whether the mesh has UVs for every face (else no `vt` records are written).
bool with_uvs(const QuadMesh& mesh) { return mesh.face_uvs.size() == mesh.faces.size(); }

/// The comment line with the mesh's vertex and face counts.
void header(BlockWriter& w, const QuadMesh& mesh) {
    Text& text = w.text();
    text.reserve(128);
    text.put("# qex quad mesh: ");
    text.number(mesh.positions.size());
    text.put(" vertices, ");
    text.number(mesh.faces.size());
    text.put(" faces\n");
}

/// A `v` record per vertex.
void positions(BlockWriter& w, const QuadMesh& mesh) {
    for (const auto& x : mesh.positions) {
        Text& text = w.text();
        text.reserve(4 * kNumber);
        text.put('v');
        for (double c : x) text.put(' '), text.number(c);
        text.put('\n');
        w.ready();
    }
}

/// A `vt` record per face corner, faces in order, if every face has its UVs.
void corner_uvs(BlockWriter& w, const QuadMesh& mesh) {
    if (!with_uvs(mesh)) return;
    for (const auto& uvs : mesh.face_uvs)
        for (const auto& t : uvs) {
            Text& text = w.text();
            text.reserve(2 * kNumber + 8);
            text.put("vt ");
            text.number(static_cast<long long>(t[0]));
            text.put(' ');
            text.number(static_cast<long long>(t[1]));
            text.put('\n');
            w.ready();
        }
}

/// An `f` record per face; its corners name their `vt` records (in the order corner_uvs() wrote
/// them) if every face has its UVs.
void faces(BlockWriter& w, const QuadMesh& mesh) {
    const bool uvs = with_uvs(mesh);
    std::size_t t = 1;
    for (std::size_t i = 0; i < mesh.faces.size(); ++i) {
        // Block by block within a face too, so memory does not grow with the longest face.
        const auto& face = mesh.faces[i];
        w.text().reserve(1);
        w.text().put('f');
        for (std::size_t k = 0; k < face.size(); ++k) {
            Text& text = w.text();
            text.reserve(2 * kNumber + 2);
            text.put(' ');
            text.number(face[k] + 1);
            if (uvs && k < mesh.face_uvs[i].size()) text.put('/'), text.number(t++);
            w.ready();
        }
        w.text().reserve(1);
        w.text().put('\n');
        w.ready();
    }
}

} // namespace

namespace io_detail {

IoError close_and_rename(std::FILE* f, const std::string& tmp, const std::string& path) {
    const bool ok = std::ferror(f) == 0;
    if (std::fclose(f) != 0 || !ok) {
        std::remove(tmp.c_str());
        return {IoError::Code::CannotWrite, "error while writing '" + tmp + "'", 0};
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        std::remove(tmp.c_str());
        return {IoError::Code::CannotWrite, "cannot rename '" + tmp + "' to '" + path + "'", 0};
    }
    return {};
}

} // namespace io_detail

IoError write_obj(const std::string& path, const QuadMesh& mesh, int threads) {
    const std::string tmp = path + ".tmp";
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) return {IoError::Code::CannotWrite, "cannot write '" + tmp + "'", 0};
    try {
        // A second thread pays only on large meshes (std::thread: with or without OpenMP).
        const bool cores = threads == 0 ? std::thread::hardware_concurrency() > 1 : threads > 1;
        BlockWriter w(f, cores && mesh.faces.size() >= kOverlapFaces);
        header(w, mesh);
        positions(w, mesh);
        corner_uvs(w, mesh);
        faces(w, mesh);
    } catch (const std::bad_alloc&) { // the blocks' memory: no file, an error
        std::fclose(f);
        std::remove(tmp.c_str());
        return {IoError::Code::CannotWrite, "out of memory while writing '" + tmp + "'", 0};
    }
    return io_detail::close_and_rename(f, tmp, path);
}

} // namespace qex
