"""The evaluation contract and what every body, load and solver shares: the contributors'
contract (``contract``), the declared interfaces (``protocols``), the line-body hook
(``lines``), what a saved step holds (``records``), nodes, inputs, quadratic constraints
and the linear solves on the fixed pattern (``linalg``)."""
