#include "emlt/core/cluster.h"

#include <cstdio>
#include <cstdlib>

#include "emlt/core/error.h"

#if EMLT_WITH_MPI
#include <mpi.h>

#include <algorithm>
#include <climits>
#endif

namespace emlt::cluster {

namespace {
// Whether a launcher (mpirun, mpiexec, srun) started this process: Open MPI, MPICH's Hydra
// and PMIx-based launchers each leave their variables. A plain run does not initialise MPI
// at all, so it behaves exactly as a build without MPI (Open MPI would otherwise start a
// singleton runtime).
bool launched_by_mpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "PMI_RANK"})
    if (std::getenv(name)) return true;
  return false;
}
}  // namespace

#if EMLT_WITH_MPI

namespace {

bool g_initialised = false;
int g_rank = 0, g_size = 1;

// MPI counts are ints: large vectors go in pieces of at most 2^28 elements.
constexpr size_t kPiece = size_t(1) << 28;

template <typename T>
void reduce(std::vector<T>& values, MPI_Datatype type, MPI_Op op, bool everywhere) {
  if (g_size == 1) return;
  for (size_t offset = 0; offset < values.size(); offset += kPiece) {
    const int count = int(std::min(kPiece, values.size() - offset));
    if (everywhere)
      MPI_Allreduce(MPI_IN_PLACE, values.data() + offset, count, type, op, MPI_COMM_WORLD);
    else if (g_rank == 0)
      MPI_Reduce(MPI_IN_PLACE, values.data() + offset, count, type, op, 0, MPI_COMM_WORLD);
    else
      MPI_Reduce(values.data() + offset, nullptr, count, type, op, 0, MPI_COMM_WORLD);
  }
}

std::string g_gathered;  // the buffer of the last gather, reused

// `known`: every rank's length, when every rank has them (else they are gathered first).
std::vector<std::string_view> gather(const std::string& mine, bool everywhere,
                                     std::span<const uint64_t> known = {}) {
  if (g_size == 1) return {mine};
  if (mine.size() > size_t(INT_MAX)) throw Error("MPI: a rank's share is over 2 GB");
  const int length = int(mine.size());
  std::vector<int> lengths(size_t(g_size), 0);
  if (!known.empty()) {
    for (int r = 0; r < g_size; ++r) {
      if (known[size_t(r)] > uint64_t(INT_MAX)) throw Error("MPI: a rank's share is over 2 GB");
      lengths[size_t(r)] = int(known[size_t(r)]);
    }
    if (lengths[size_t(g_rank)] != length) throw Error("MPI: a rank's share changed its length");
  } else if (everywhere) {
    MPI_Allgather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, MPI_COMM_WORLD);
  } else {
    MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  }
  std::vector<int> offsets(size_t(g_size), 0);
  int64_t total = 0;
  for (int r = 0; r < g_size; ++r) {
    offsets[size_t(r)] = int(total);
    total += lengths[size_t(r)];
  }
  if (total > INT_MAX) throw Error("MPI: the gathered shares are over 2 GB");
  std::string& all = g_gathered;
  all.resize(size_t(everywhere || g_rank == 0 ? total : 0));
  if (everywhere)
    MPI_Allgatherv(mine.data(), length, MPI_BYTE, all.data(), lengths.data(), offsets.data(),
                   MPI_BYTE, MPI_COMM_WORLD);
  else
    MPI_Gatherv(mine.data(), length, MPI_BYTE, all.data(), lengths.data(), offsets.data(),
                MPI_BYTE, 0, MPI_COMM_WORLD);
  std::vector<std::string_view> parts;
  if (!everywhere && g_rank != 0) return parts;
  for (int r = 0; r < g_size; ++r)
    parts.push_back(std::string_view(all).substr(size_t(offsets[size_t(r)]), size_t(lengths[size_t(r)])));
  return parts;
}

}  // namespace

void init(int* argc, char*** argv) {
  if (!launched_by_mpi()) return;
  int provided = 0;
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  g_initialised = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_size);
}

void finalize() {
  if (g_initialised) MPI_Finalize();
  g_initialised = false;
}

void abort(int status) {
  if (g_initialised && g_size > 1) MPI_Abort(MPI_COMM_WORLD, status);
  std::exit(status);
}

int rank() { return g_rank; }
int size() { return g_size; }

std::string library_version() {
  char version[MPI_MAX_LIBRARY_VERSION_STRING];
  int length = 0;
  MPI_Get_library_version(version, &length);
  std::string text(version, size_t(length));
  return text.substr(0, text.find_first_of(",\n"));
}

void sum_to_root(std::vector<int64_t>& v) { reduce(v, MPI_INT64_T, MPI_SUM, false); }
void sum_to_root(std::vector<uint64_t>& v) { reduce(v, MPI_UINT64_T, MPI_SUM, false); }
void sum_to_root(std::vector<double>& v) { reduce(v, MPI_DOUBLE, MPI_SUM, false); }
void sum_to_root(std::vector<int32_t>& v) { reduce(v, MPI_INT32_T, MPI_SUM, false); }
void sum_everywhere(std::vector<uint64_t>& v) { reduce(v, MPI_UINT64_T, MPI_SUM, true); }
void max_everywhere(std::vector<uint64_t>& v) { reduce(v, MPI_UINT64_T, MPI_MAX, true); }

std::vector<std::string_view> gather_to_root(const std::string& mine) { return gather(mine, false); }
std::vector<std::string_view> gather_everywhere(const std::string& mine) { return gather(mine, true); }
std::vector<std::string_view> gather_everywhere(const std::string& mine,
                                                std::span<const uint64_t> lengths) {
  return gather(mine, true, lengths);
}

void broadcast(std::string& data) {
  if (g_size == 1) return;
  uint64_t length = data.size();
  MPI_Bcast(&length, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
  if (length > uint64_t(INT_MAX)) throw Error("MPI: a broadcast is over 2 GB");
  data.resize(length);
  MPI_Bcast(data.data(), int(length), MPI_BYTE, 0, MPI_COMM_WORLD);
}

#else  // one process

void init(int*, char***) {
  // Every process of the launch would render the whole image and write the same files.
  if (launched_by_mpi())
    std::fprintf(stderr,
                 "emlt: warning: started by an MPI launcher, but this emlt was built without "
                 "MPI (EMLT_WITH_MPI=OFF): each process renders the whole image on its own\n");
}
void finalize() {}
void abort(int status) { std::exit(status); }
int rank() { return 0; }
int size() { return 1; }
std::string library_version() { return ""; }
void sum_to_root(std::vector<int64_t>&) {}
void sum_to_root(std::vector<uint64_t>&) {}
void sum_to_root(std::vector<double>&) {}
void sum_to_root(std::vector<int32_t>&) {}
void sum_everywhere(std::vector<uint64_t>&) {}
void max_everywhere(std::vector<uint64_t>&) {}
std::vector<std::string_view> gather_to_root(const std::string& mine) { return {mine}; }
std::vector<std::string_view> gather_everywhere(const std::string& mine) { return {mine}; }
std::vector<std::string_view> gather_everywhere(const std::string& mine,
                                                std::span<const uint64_t>) {
  return {mine};
}
void broadcast(std::string&) {}

#endif

void agree_on_error(const std::string& error) {
  if (size() == 1) {
    if (!error.empty()) throw Error(error);
    return;
  }
  for (const std::string_view e : gather_everywhere(error))
    if (!e.empty()) throw Error(std::string(e));
}

}  // namespace emlt::cluster
