!> Totals of a pass over the particles that vectorise and do not depend on the vector width: a loop
!> over particles works in blocks of `block_size`, and each total of a block is kept in `lanes`
!> partial sums (particle i of a block adds to lane mod(i - 1, lanes) + 1), combined in lane order
!> at the end. A single running sum would make every particle wait for the previous one's add.
!> The largest particle move is tracked the same way, and its particle found once, at the end.
module mpm_lanes
   use mpm_kinds, only: dp
   implicit none
   private
   public :: block_size, lanes, largest_move_t, add_lanes, min_lanes, lane_total, track_largest_move, &
             furthest_particle

   !> Particles per block: the block's buffers stay in L1.
   integer, parameter :: block_size = 64
   !> Partial sums per total: one AVX-512 vector of doubles (four SSE2 vectors without -march).
   integer, parameter :: lanes = 8

   !> The largest particle move so far, with the moves of the block where it happened.
   type :: largest_move_t
      real(dp) :: value = 0.0_dp
      integer :: first = 0, count = 0
      real(dp) :: moves(block_size)
   end type largest_move_t

contains

   !> lane_sums += the n values of a block, lane by lane.
   pure subroutine add_lanes(n, values, lane_sums)
      integer, intent(in) :: n
      real(dp), intent(in) :: values(n)
      real(dp), intent(inout) :: lane_sums(lanes)
      integer :: i, r
      do i = 1, n - lanes + 1, lanes
         lane_sums = lane_sums + values(i:i + lanes - 1)
      end do
      r = mod(n, lanes)
      if (r > 0) lane_sums(1:r) = lane_sums(1:r) + values(n - r + 1:n)
   end subroutine add_lanes

   !> lane_min = min(lane_min, the n values of a block), lane by lane.
   pure subroutine min_lanes(n, values, lane_min)
      integer, intent(in) :: n
      real(dp), intent(in) :: values(n)
      real(dp), intent(inout) :: lane_min(lanes)
      integer :: i, r
      do i = 1, n - lanes + 1, lanes
         lane_min = min(lane_min, values(i:i + lanes - 1))
      end do
      r = mod(n, lanes)
      if (r > 0) lane_min(1:r) = min(lane_min(1:r), values(n - r + 1:n))
   end subroutine min_lanes

   !> Sum of the lanes, in lane order.
   pure real(dp) function lane_total(lane_sums) result(total)
      real(dp), intent(in) :: lane_sums(lanes)
      integer :: l
      total = 0.0_dp
      do l = 1, lanes
         total = total + lane_sums(l)
      end do
   end function lane_total

   !> Largest move of a block (its first particle b0), kept with the block's moves when it beats the
   !> largest so far (strictly: the first block keeps it, as a single loop would).
   pure subroutine track_largest_move(n, b0, move, largest)
      integer, intent(in) :: n, b0
      real(dp), intent(in) :: move(n)
      type(largest_move_t), intent(inout) :: largest
      real(dp) :: lane_max(lanes), block_max
      integer :: i, r
      lane_max = 0.0_dp
      do i = 1, n - lanes + 1, lanes
         lane_max = max(lane_max, move(i:i + lanes - 1))
      end do
      r = mod(n, lanes)
      if (r > 0) lane_max(1:r) = max(lane_max(1:r), move(n - r + 1:n))
      block_max = maxval(lane_max)
      if (block_max > largest%value) then
         largest%value = block_max
         largest%first = b0
         largest%count = n
         largest%moves(1:n) = move(1:n)
      end if
   end subroutine track_largest_move

   !> The first particle that made the largest move (0 if none moved).
   pure integer function furthest_particle(largest) result(p)
      type(largest_move_t), intent(in) :: largest
      p = 0
      if (largest%count > 0) p = largest%first - 1 + maxloc(largest%moves(1:largest%count), 1)
   end function furthest_particle
end module mpm_lanes
