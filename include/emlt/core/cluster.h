#pragma once
// The processes of a render: one, or R of them under `mpirun -n R` (Open MPI, MPICH). Each
// rank takes a fixed share of the work, derived from the rank count alone, and the shares
// are merged exactly, so the image is the single-process image bit for bit:
//
// * Merges only ever add integers (fixed-point films, counters) or add a value to zeros
//   (a pixel, chain or block is worked on by exactly one rank; the others hold +0.0, and
//   x + 0.0 == x), so MPI's reduction order cannot change a bit.
// * Sequences that must be added in order (BDPT's light-tracing splats, the bootstrap's
//   blocks) are gathered and added in their single-process order.
//
// Without MPI (EMLT_WITH_MPI off, or a plain run) every function below is the trivial
// one-process version. Only the calling thread talks to MPI (MPI_THREAD_FUNNELED); the TBB
// workers never do.
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace emlt::cluster {

// Called once by main() before anything else, and at exit.
void init(int* argc, char*** argv);
void finalize();
// Ends every rank at once (a failure after the ranks parted ways); never returns.
[[noreturn]] void abort(int status);

int rank();
int size();
inline bool is_root() { return rank() == 0; }
// "Open MPI v4.1.4 ..." or "" without MPI.
std::string library_version();

// The share [begin, end) of `count` items that rank `r` of `ranks` takes: contiguous,
// sizes differing by at most one.
inline std::pair<uint64_t, uint64_t> share(uint64_t count, int r, int ranks) {
  return {count * uint64_t(r) / uint64_t(ranks), count * uint64_t(r + 1) / uint64_t(ranks)};
}
inline std::pair<uint64_t, uint64_t> share(uint64_t count) { return share(count, rank(), size()); }

// Element-wise sums, on rank 0 only (the other ranks' vectors are left as they were) or on
// every rank.
void sum_to_root(std::vector<int64_t>& values);
void sum_to_root(std::vector<uint64_t>& values);
void sum_to_root(std::vector<double>& values);
void sum_to_root(std::vector<int32_t>& values);
void sum_everywhere(std::vector<uint64_t>& values);
// Element-wise maxima, on every rank.
void max_everywhere(std::vector<uint64_t>& values);

// Every rank's bytes, in rank order, on rank 0 (empty elsewhere) or on every rank. The
// views stay valid until the next gather (the buffer is kept: EMLT gathers megabytes at
// every swap, and fresh pages for each would cost more than the copy).
std::vector<std::string_view> gather_to_root(const std::string& mine);
std::vector<std::string_view> gather_everywhere(const std::string& mine);
// The same when every rank already knows every rank's length (lengths[r], in bytes).
std::vector<std::string_view> gather_everywhere(const std::string& mine,
                                                std::span<const uint64_t> lengths);
// Rank 0's bytes on every rank.
void broadcast(std::string& data);

// After the part of a command where ranks may fail on their own (reading the scene, the
// checkpoint): every rank passes its error ("" if none); if any rank failed, every rank
// throws emlt::Error with the lowest failing rank's message.
void agree_on_error(const std::string& error);

}  // namespace emlt::cluster
