// GoogleTest main for the MPI tests of the physics layer: deal.II initializes MPI (and p4est),
// Tpetra then only Kokkos; only rank 0 reports, so that an MPI test prints one summary.
#include <deal.II/base/mpi.h>

#include <Tpetra_Core.hpp>
#include <gtest/gtest.h>

int main(int argc, char** argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  Tpetra::ScopeGuard                       tpetra(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  if (dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) != 0)
    delete ::testing::UnitTest::GetInstance()->listeners().Release(
        ::testing::UnitTest::GetInstance()->listeners().default_result_printer());
  return RUN_ALL_TESTS();
}
