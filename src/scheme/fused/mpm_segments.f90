!> The fused stepper's work split of the particle passes (segments_t) and its checkpoint. A segment
!> is a contiguous range of elements and of the particles in them (particles are kept sorted by
!> element); the fused kernels (mpm_transfer) plan the segments, fill them pass by pass and read
!> them back in a fixed order, so that every sum has the same association whatever the number of
!> threads. The run's stepper (mpm_fused's fused_stepper_t) owns one; nothing below the scheme layer
!> knows of them.
module mpm_segments
   use mpm_kinds, only: dp
   use mpm_state, only: state_t
   implicit none
   private
   public :: segments_t, share_count, sync_segments

   !> Number of per-element shares a particle pass accumulates (mass left/right, momentum
   !> left/right, stress*volume, external force left/right): the layout of the halo buffers below.
   integer, parameter :: share_count = 7

   !> What a pass records of one segment, read back in segment order after the pass (finish_pass). One
   !> record per segment, in one allocation: a small run's step touched a cache line (and a descriptor)
   !> for each of eleven arrays of these, and its data then overflowed sets of the level-1 cache.
   type :: segment_tally_t
      !> displacement (sum of x - X), kinetic and strain energy, plastic work
      real(dp) :: sums(4) = 0.0_dp
      !> smallest J; largest move in cells and its particle; first particle outside the grid
      real(dp) :: min_volume_ratio = 0.0_dp, max_cell_move = 0.0_dp
      integer :: furthest = 0, outside = 0
      !> the first and last new cell of its particles; whether some were out of order or moved far
      integer :: first_cell = 0, last_cell = 0
      logical :: unsorted = .false., far = .false.
      !> Bodies on stacked fields (a segment lies in one body): its particles' sum m v and smallest stress.
      real(dp) :: body_momentum = 0.0_dp, min_stress = 0.0_dp
   end type segment_tally_t

   !> How the particle passes split one run into segments: contiguous element ranges, fixed by the
   !> problem size only (never by the thread count), each holding a contiguous range of particles.
   !> A segment sums the shares of its own elements in particle order; shares for the element just
   !> left or right of its range go to its halo buffers, added in a fixed order after the pass.
   !> Filled by the first P2G (mpm_transfer's plan_segments), used by every later pass; no allocation
   !> in the time loop.
   type :: segments_t
      integer :: count = 0
      !> Segment k covers elements first_element(k) .. first_element(k+1)-1.
      integer, allocatable :: first_element(:)
      !> ... and particles first_particle(k) .. first_particle(k+1)-1 (found at the start of a pass).
      integer, allocatable :: first_particle(:)
      !> Shares for element first_element(k)-1 (halo_left) and first_element(k+1) (halo_right).
      real(dp), allocatable :: halo_left(:, :), halo_right(:, :)
      !> Each segment's totals of the last pass (tally(k): segment k)
      type(segment_tally_t), allocatable :: tally(:)
      !> Bodies on stacked fields (clear_written): each segment clears, of each kind of share (mass,
      !> momentum, stress, force: the second index), only the elements written(1, :, k) .. written(2, :, k)
      !> that its last pass of that kind wrote (every other element of its range is zero), not its whole
      !> range: a body's field spans the whole domain but its particles reach only the cells they fill.
      logical :: clear_written = .false.
      integer, allocatable :: written(:, :, :)
      !> Whether the kernels ask for particle data ahead of use (set by plan_segments from the size of
      !> the run; see mpm_transfer's prefetch_bytes).
      logical :: prefetch = .false.
   end type segments_t

contains

   !> What a step leaves in the segments for the next (the particle ranges the next pass starts its
   !> search from, the halo shares, the record of what each segment wrote) to or from `state` (under
   !> `prefix`.*, as state%saving says), into segments planned for the same run.
   subroutine sync_segments(state, prefix, seg)
      type(state_t), intent(inout) :: state
      character(len=*), intent(in) :: prefix
      type(segments_t), intent(inout) :: seg
      integer, allocatable :: flat(:)
      call state%sync(prefix//'.first_particle', seg%first_particle)
      call state%sync(prefix//'.halo_left', seg%halo_left)
      call state%sync(prefix//'.halo_right', seg%halo_right)
      if (.not. allocated(seg%written)) return
      ! (flat: the state holds arrays of rank 2 at most)
      if (state%saving) flat = reshape(seg%written, [size(seg%written)])
      call state%sync(prefix//'.written', flat)
      if (.not. state%saving .and. allocated(flat)) then
         if (size(flat) == size(seg%written)) seg%written = reshape(flat, shape(seg%written))
      end if
   end subroutine sync_segments
end module mpm_segments
