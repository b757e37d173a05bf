"""A node of a body, as constraints and loads address it (``cable.node(i)``): a leaf module,
so that bodies, constraints and the system all depend on it and not on each other."""


class Node:
    """A node of a body, as used by constraints and loads: ``cable.node(i)``.

    Attributes
    ----------
    body : Cable or any body with nodes
        The body the node belongs to, which declares ``node_dofs(index)`` (the node's
        local coordinates: its position first, then its slope if ``has_slopes``) and
        ``has_slopes`` (whether its nodes carry a slope ``r_x``): a cable, or a user's
        line body.
    index : int
        Index of the node in the body (non-negative).
    position_dofs, slope_dofs : int ndarray (3,)
        The body's local coordinates of the node's position ``r`` and slope ``r_x``; a
        node without a slope (a linear element's) refuses ``slope_dofs`` with a
        ``ValueError``.
    has_twist : bool
        Whether the node carries a twist angle (its body declares ``twist_dofs(index)``,
        the local coordinate of the node's twist: a rod); then ``twist_dofs`` is it
        (int ndarray (1,)).

    Examples
    --------
    >>> import skfem_cable as sc
    >>> cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, sc.Section.circular(1e-3, 2e11, 7850.0))
    >>> tip = cable.node(-1)
    >>> tip, tip.position_dofs.tolist(), tip.slope_dofs.tolist()
    (Node(cable, 2), [12, 13, 14], [15, 16, 17])
    """

    def __init__(self, body, index):
        self.body = body
        self.index = index

    @property
    def position_dofs(self):
        """Local coordinates of the node's position ``r`` in its body."""
        return self.body.node_dofs(self.index)[:3]

    @property
    def has_slope(self):
        """Whether the node carries a slope ``r_x`` (its element has one)."""
        return self.body.has_slopes

    @property
    def slope_dofs(self):
        """Local coordinates of the node's slope ``r_x`` in its body."""
        if not self.has_slope:
            raise ValueError(f"{self!r} has no slope: its body {self.body.name!r} has "
                             "positions only at its nodes; a clamp or a slope constraint "
                             "needs an element with slopes (e.g. element='hermite3')")
        return self.body.node_dofs(self.index)[3:6]

    @property
    def has_twist(self):
        """Whether the node carries a twist angle (its body declares ``twist_dofs``)."""
        return callable(getattr(self.body, "twist_dofs", None))

    @property
    def twist_dofs(self):
        """Local coordinate (1,) of the node's twist angle in its body."""
        if not self.has_twist:
            raise ValueError(f"{self!r} has no twist: its body {self.body.name!r} is not a "
                             "rod (it declares no twist_dofs)")
        return self.body.twist_dofs(self.index)

    def __repr__(self):
        return f"Node({self.body.name}, {self.index})"
