// GoogleTest main for MPI tests: Tpetra initializes MPI (and Kokkos) around the whole run.
#include <Tpetra_Core.hpp>
#include <gtest/gtest.h>

int main(int argc, char** argv)
{
  Tpetra::ScopeGuard mpi(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  // Only rank 0 reports, so that an MPI test prints one summary.
  if (Tpetra::getDefaultComm()->getRank() != 0)
    delete ::testing::UnitTest::GetInstance()->listeners().Release(
        ::testing::UnitTest::GetInstance()->listeners().default_result_printer());
  return RUN_ALL_TESTS();
}
